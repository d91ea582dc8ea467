#include "common/reservoir_median.h"

#include <algorithm>

#include <fmt/format.h>

#include "common/errors.h"
#include "common/split_mix64.h"

namespace ecpsim {

ReservoirMedian::ReservoirMedian(std::vector<double> sample, std::int64_t count)
    : sample_(std::move(sample)), count_(count) {
  const std::int64_t expected = std::min<std::int64_t>(count, kCapacity);
  if (count < 0 || static_cast<std::int64_t>(sample_.size()) != expected) {
    throw InputError(
        fmt::format("median sample of {} values after {} values: expected "
                    "min(count, {}) values",
                    sample_.size(), count, kCapacity));
  }
}

void ReservoirMedian::Add(double value) {
  ++count_;
  if (count_ <= kCapacity) {
    sample_.push_back(value);
    return;
  }
  // algorithm R: the n-th value replaces a uniformly chosen slot with probability kCapacity / n
  // (the modulo's bias is below n / 2^64)
  const std::uint64_t slot =
      SplitMix64(static_cast<std::uint64_t>(count_)) % static_cast<std::uint64_t>(count_);
  if (slot < static_cast<std::uint64_t>(kCapacity)) sample_[slot] = value;
}

double ReservoirMedian::Median() const {
  if (sample_.empty()) return 0;
  std::vector<double> values = sample_;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  if (values.size() % 2 == 1) return values[mid];
  const double upper = values[mid];
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + mid));
}

}  // namespace ecpsim
