// Seeded random numbers: in range, reproducible per (seed, stream), independent across streams.

#include "evaluation/seeded_random.h"

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "tests/tolerances.h"

namespace ecpsim::evaluation {
namespace {

constexpr int kDraws = 10000;

TEST(SeededRandomTest, DrawsStayInTheirRanges) {
  SeededRandom random(1, 0);
  std::set<int> integers;
  double sum = 0;
  for (int i = 0; i < kDraws; ++i) {
    const double u = random.Uniform(0, 1);
    EXPECT_GE(u, 0);
    EXPECT_LT(u, 1);
    sum += u;
    const double l = random.LogUniform(1e-3, 1e2);
    EXPECT_GE(l, 1e-3 * (1 - kUnitRoundOff));  // relative: the round-off of exp and log
    EXPECT_LE(l, 1e2 * (1 + kUnitRoundOff));
    const int k = random.Integer(2, 4);
    EXPECT_GE(k, 2);
    EXPECT_LE(k, 4);
    integers.insert(k);
    EXPECT_NEAR(random.UnitVector().norm(), 1, kUnitRoundOff);
    EXPECT_LE(random.InBall().norm(), 1 + kUnitRoundOff);
    EXPECT_NEAR(random.Rotation().norm(), 1, kUnitRoundOff);
  }
  EXPECT_EQ(integers.size(), 3u);
  // the mean of uniform draws: 1/2 within 5 standard deviations, sqrt(1/12 / kDraws)
  EXPECT_NEAR(sum / kDraws, 0.5, 5 * std::sqrt(1.0 / 12 / kDraws));
}

TEST(SeededRandomTest, SameSeedAndStreamSameDrawsOthersDiffer) {
  SeededRandom a(7, 3), b(7, 3), other_stream(7, 4), other_seed(8, 3);
  int same_stream = 0, same_seed = 0;
  for (int i = 0; i < 100; ++i) {
    const double x = a.Uniform(0, 1);
    EXPECT_EQ(x, b.Uniform(0, 1));
    same_stream += x == other_stream.Uniform(0, 1);
    same_seed += x == other_seed.Uniform(0, 1);
  }
  EXPECT_EQ(same_stream, 0);
  EXPECT_EQ(same_seed, 0);
}

TEST(StableHashTest, IsFnv1a) {
  // FNV-1a's published test vectors (64-bit): "" and "a"
  EXPECT_EQ(StableHash(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(StableHash("a"), 0xaf63dc4c8601ec8cULL);
}

}  // namespace
}  // namespace ecpsim::evaluation
