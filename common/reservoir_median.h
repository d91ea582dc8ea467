#pragma once
// The median of a stream of any length in bounded memory: a uniform random sample of fixed size
// (reservoir sampling, Vitter's algorithm R) with a fixed, seedless replacement sequence, so the
// same stream always gives the same median.

#include <cstdint>
#include <vector>

namespace ecpsim {

class ReservoirMedian {
 public:
  /// The sample size: 128 kB of doubles. Up to this many values the median is exact; beyond,
  /// it is the sample's median, whose rank in the whole stream is within ±1.2 % of the middle
  /// with probability 99.7 % (3 standard deviations of a sample median's quantile,
  /// 0.5 / sqrt(kCapacity) = 0.39 % each), whatever the stream's length or order.
  static constexpr int kCapacity = 16384;

  ReservoirMedian() = default;
  /// A reservoir that has seen `count` values and kept `sample` (from sample() and count(), to
  /// continue a stream later).
  /// @throws InputError if sample.size() is not min(count, kCapacity).
  ReservoirMedian(std::vector<double> sample, std::int64_t count);

  void Add(double value);

  /// The median of the values added (the mean of the two middle ones for an even count); 0 when
  /// none were added.
  double Median() const;

  std::int64_t count() const { return count_; }
  const std::vector<double>& sample() const { return sample_; }

 private:
  std::vector<double> sample_;
  std::int64_t count_ = 0;
};

}  // namespace ecpsim
