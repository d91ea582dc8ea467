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
  // a mesh's inertia integrates L⁵ (times a density up to 1e±150 would leave the magnitude
  // range, which the density and mass checks catch)
  EXPECT_LE(std::pow(kMaxLength, 5), kMaxMagnitude);
  EXPECT_GE(std::pow(kMinLength, 5), kMinMagnitude);
  // and their squares are finite, normal doubles
  EXPECT_TRUE(std::isnormal(std::pow(kMaxLength, 10)));
  EXPECT_TRUE(std::isnormal(std::pow(kMinLength, 10)));
}

TEST(SceneLimitsTest, StepTimesStayDistinctUpToTheStepLimit) {
  // t = k·h rounded once: (2k + 1)·2^-53 < 1 keeps fl((k+1)h) > fl(kh) for every h
  const double k = static_cast<double>(kMaxSteps - 1);
  EXPECT_LT((2 * k + 1) * std::ldexp(1.0, -53), 1.0);
  for (const double h : {0.01, 1e-5, 0.1 / 3, 7.3}) {
    EXPECT_GT((k + 1) * h, k * h) << h;
  }
}

TEST(SceneLimitsTest, PositionsWithinTheDistanceLimitResolveBelowTheEngineTolerance) {
  // the engine's geometric tolerances are 1e-9 of a body's size (hull_model.cpp)
  constexpr double kGeometricRelTol = 1e-9;
  EXPECT_LT(kMaxDistanceInSizes * DBL_EPSILON, kGeometricRelTol);
}

TEST(SceneLimitsTest, PlannedStepsIsTheCeilingWithSlackForRoundOff) {
  EXPECT_EQ(PlannedSteps(0.5, 0.01), 50);  // 49.999999999999993 in floating point
  EXPECT_EQ(PlannedSteps(1, 0.3), 4);      // 3.33...: a last, full step past the duration
  EXPECT_EQ(PlannedSteps(1, 1), 1);
  EXPECT_EQ(PlannedSteps(0.7, 0.1), 7);
  EXPECT_EQ(PlannedSteps(1, 1e-7), 10'000'000);
  // the slack is in steps, not in proportion to the count: 1e10 steps are 1e10, and 0.3 of a
  // step past them is one more
  EXPECT_EQ(PlannedSteps(1, 1e-10), 10'000'000'000L);
  EXPECT_EQ(PlannedSteps(1e10 + 0.3, 1), 10'000'000'001L);
}

TEST(SceneLimitsTest, StepCountProblemNamesTheCountBeyondTheLimit) {
  EXPECT_EQ(StepCountProblem(1, 1e-7), "");
  EXPECT_EQ(StepCountProblem(4, 0.01), "");
  EXPECT_EQ(StepCountProblem(1, 1e-10), "");  // 1e10 steps: long, but a valid run
  EXPECT_THAT(StepCountProblem(1, 1e-16),
              HasSubstr("at most 4503599627370496 steps per run, here duration / h = 1 / 1e-16 = "
                        "1e+16"));
  EXPECT_THAT(StepCountProblem(1e20, 0.01), HasSubstr("1e+22 steps"));
  EXPECT_NE(StepCountProblem(1, std::nan("")), "");
}

TEST(SceneLimitsTest, OutOfRangeAcceptsTheClosedRangeAndNeverNaN) {
  EXPECT_EQ(OutOfRange(kMinLength, kLengthRange), "");
  EXPECT_EQ(OutOfRange(kMaxLength, kLengthRange), "");
  EXPECT_EQ(OutOfRange(0.5, kLengthRange), "");
  EXPECT_EQ(OutOfRange(2e20, kLengthRange), "a length in [1e-20, 1e+20] m");
  EXPECT_EQ(OutOfRange(1e-21, kLengthRange), "a length in [1e-20, 1e+20] m");
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
