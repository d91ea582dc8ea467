#include "common/reservoir_median.h"

#include <algorithm>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim {
namespace {

// SplitMix64's output function (Steele, Lea, Flood 2014): a bijective mix of a 64-bit counter
// whose outputs pass BigCrush; here it turns the value's position into its replacement draw
std::uint64_t Mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

ReservoirMedian::ReservoirMedian(std::vector<double> sample, std::int64_t count)
    : sample_(std::move(sample)), count_(count) {
  const std::int64_t expected = std::min<std::int64_t>(count, kCapacity);
  if (count < 0 || static_cast<std::int64_t>(sample_.size()) != expected) {
    throw InputError(fmt::format("median sample of {} values after {} values: expected "
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
  const std::uint64_t slot = Mix(static_cast<std::uint64_t>(count_)) %
                             static_cast<std::uint64_t>(count_);
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
