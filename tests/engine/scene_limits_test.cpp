#include "engine/scene_limits.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>

namespace ecpsim::engine {
namespace {

using ::testing::HasSubstr;

// the derivations written beside the constants, checked against the doubles themselves

TEST(SceneLimitsTest, MagnitudesSquareToFiniteNormalDoubles) {
  EXPECT_GE(kMinMagnitude * kMinMagnitude, DBL_MIN);
  EXPECT_TRUE(std::isnormal(kMinMagnitude * kMinMagnitude));
  EXPECT_TRUE(std::isfinite(kMaxMagnitude * kMaxMagnitude));
  // a sum of a few squares too (the norm of a 3- or 4-vector)
  EXPECT_TRUE(std::isfinite(4 * kMaxMagnitude * kMaxMagnitude));
}

TEST(SceneLimitsTest, LengthsToTheFifthPowerStayInTheMagnitudeRange) {
  // equal to the magnitude bounds up to the round-off of pow
  EXPECT_NEAR(std::pow(kMaxLength, 5) / kMaxMagnitude, 1, 1e-15);
  EXPECT_NEAR(std::pow(kMinLength, 5) / kMinMagnitude, 1, 1e-15);
  // so their squares are finite, normal doubles
  EXPECT_TRUE(std::isnormal(std::pow(kMaxLength, 10)));
  EXPECT_TRUE(std::isnormal(std::pow(kMinLength, 10)));
}

TEST(SceneLimitsTest, StepLimitKeepsTheRoundOffOfTimeBelowOnePercentOfAStep) {
  // N additions of h to t ≤ duration, each off by at most ε·duration/2: N²·ε/2 steps in all
  const double n = static_cast<double>(kMaxSteps);
  EXPECT_LT(n * n * DBL_EPSILON / 2, 0.012);
  // and t + h > t with room to spare for the smallest h allowed, duration / kMaxSteps
  const double duration = 3;
  EXPECT_GT(duration + duration / n, duration);
}

TEST(SceneLimitsTest, PositionsWithinTheDistanceLimitResolveBelowTheEngineTolerance) {
  // the engine's geometric tolerances are 1e-9 of a body's size (time_step.cpp)
  EXPECT_LT(kMaxDistanceInSizes * DBL_EPSILON, 1e-9);
}

TEST(SceneLimitsTest, PlannedStepsIsTheCeilingWithSlackForRoundOff) {
  EXPECT_EQ(PlannedSteps(0.5, 0.01), 50);  // 49.999999999999993 in floating point
  EXPECT_EQ(PlannedSteps(1, 0.3), 4);      // 3.33...: a last, full step past the duration
  EXPECT_EQ(PlannedSteps(1, 1), 1);
  EXPECT_EQ(PlannedSteps(0.7, 0.1), 7);
  EXPECT_EQ(PlannedSteps(1, 1e-7), kMaxSteps);
}

TEST(SceneLimitsTest, StepCountProblemNamesTheCountBeyondTheLimit) {
  EXPECT_EQ(StepCountProblem(1, 1e-7), "");
  EXPECT_EQ(StepCountProblem(4, 0.01), "");
  EXPECT_THAT(StepCountProblem(1, 1e-8),
              HasSubstr("at most 10000000 steps per run, here duration / h = 1 / 1e-08 = 1e+08"));
  EXPECT_THAT(StepCountProblem(1e20, 0.01), HasSubstr("1e+22 steps"));
  EXPECT_NE(StepCountProblem(1, std::nan("")), "");
}

TEST(SceneLimitsTest, OutOfRangeAcceptsTheClosedRangeAndNeverNaN) {
  EXPECT_EQ(OutOfRange(kMinLength, kLengthRange), "");
  EXPECT_EQ(OutOfRange(kMaxLength, kLengthRange), "");
  EXPECT_EQ(OutOfRange(0.5, kLengthRange), "");
  EXPECT_EQ(OutOfRange(2e30, kLengthRange), "a length in [1e-30, 1e+30] m");
  EXPECT_EQ(OutOfRange(1e-31, kLengthRange), "a length in [1e-30, 1e+30] m");
  EXPECT_EQ(OutOfRange(std::nan(""), kMassRange), "a mass in [1e-150, 1e+150] kg");
  EXPECT_EQ(OutOfRange(std::numeric_limits<double>::infinity(), kMeshScaleRange),
            "a scale in [1e-06, 1e+06]");
  EXPECT_EQ(OutOfMagnitude(-1e150), "");
  EXPECT_EQ(OutOfMagnitude(0), "");
  EXPECT_EQ(OutOfMagnitude(-2e150), "a finite number within ±1e+150");
  EXPECT_NE(OutOfMagnitude(std::nan("")), "");
}

TEST(SceneLimitsTest, NamesAreLettersDigitsUnderscoreAndDash) {
  EXPECT_TRUE(IsValidName("desk_2-a"));
  EXPECT_FALSE(IsValidName(""));
  EXPECT_FALSE(IsValidName("my box"));
  EXPECT_FALSE(IsValidName(std::string("a\0b", 3)));
}

}  // namespace
}  // namespace ecpsim::engine
