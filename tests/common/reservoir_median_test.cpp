// The bounded-memory median: exact for short streams, within its stated rank accuracy for long
// ones, continued exactly from a saved sample.

#include "common/reservoir_median.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"

namespace ecpsim {
namespace {

// the rank accuracy promised in reservoir_median.h: 3 standard deviations of a sample median's
// quantile, 0.5 / sqrt(kCapacity)
const double kRankTolerance = 3 * 0.5 / std::sqrt(double{ReservoirMedian::kCapacity});

// 0, 1, ..., n - 1 in a scrambled order (a multiplier coprime to n permutes the residues)
std::vector<double> Scrambled(std::int64_t n) {
  std::vector<double> values(n);
  for (std::int64_t i = 0; i < n; ++i) values[i] = static_cast<double>((i * 7919) % n);
  return values;
}

double ExactMedian(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

TEST(ReservoirMedian, EmptyIsZero) { EXPECT_EQ(ReservoirMedian().Median(), 0); }

TEST(ReservoirMedian, ExactUpToTheCapacity) {
  constexpr std::int64_t kCapacity = ReservoirMedian::kCapacity;
  for (std::int64_t n : {std::int64_t{1}, std::int64_t{2}, std::int64_t{7}, std::int64_t{400},
                         kCapacity - 1, kCapacity}) {
    const std::vector<double> values = Scrambled(n);
    ReservoirMedian median;
    for (double v : values) median.Add(v);
    EXPECT_EQ(median.Median(), ExactMedian(values)) << n << " values";
  }
}

TEST(ReservoirMedian, LongStreamsKeepTheSampleAndTheRankAccuracy) {
  // a stream 100× the sample, in three orders: the sample is uniform whatever the order
  constexpr std::int64_t n = 100 * std::int64_t{ReservoirMedian::kCapacity};
  std::vector<double> scrambled = Scrambled(n);
  std::vector<double> rising(n), falling(n);
  for (std::int64_t i = 0; i < n; ++i) rising[i] = i, falling[i] = n - 1 - i;
  for (const std::vector<double>* values : {&scrambled, &rising, &falling}) {
    ReservoirMedian median;
    for (double v : *values) median.Add(v);
    EXPECT_EQ(median.sample().size(), static_cast<std::size_t>(ReservoirMedian::kCapacity));
    EXPECT_EQ(median.count(), n);
    // the values are their own ranks: the estimate's rank is the estimate
    EXPECT_NEAR(median.Median() / n, 0.5, kRankTolerance);
  }
}

TEST(ReservoirMedian, ContinuesExactlyFromASavedSample) {
  const std::vector<double> values = Scrambled(3 * ReservoirMedian::kCapacity + 17);
  ReservoirMedian whole, first;
  const std::size_t split = values.size() / 2;
  for (std::size_t i = 0; i < values.size(); ++i) {
    whole.Add(values[i]);
    if (i < split) first.Add(values[i]);
  }
  ReservoirMedian continued(first.sample(), first.count());
  for (std::size_t i = split; i < values.size(); ++i) continued.Add(values[i]);
  EXPECT_EQ(continued.sample(), whole.sample());
  EXPECT_EQ(continued.Median(), whole.Median());
}

TEST(ReservoirMedian, RejectsASampleThatDoesNotFitItsCount) {
  EXPECT_THAT(
      [] {
        ReservoirMedian({1.0, 2.0}, 3);
      },
      ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("2 values after 3")));
}

}  // namespace
}  // namespace ecpsim
