// The log–log fit of a cost against a size: a planted power law gives back its exponent and
// coefficient; points a log axis cannot hold are left out; too few points give no fit.

#include "evaluation/power_law_fit.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ecpsim::evaluation {
namespace {

// a few ulps of the logs (≲ 7 for x ≤ 1000) through a 2-column QR
constexpr double kFitRoundOff = 1e-12;

TEST(FitPowerLaw, APlantedPowerLawGivesItsExponent) {
  for (double k : {0.5, 1.0, 1.5, 2.0}) {
    std::vector<double> x, y;
    for (double n : {1.0, 4.0, 16.0, 64.0, 250.0, 1000.0}) {
      x.push_back(n);
      y.push_back(3e-6 * std::pow(n, k));
    }
    const auto fit = FitPowerLaw(x, y);
    ASSERT_TRUE(fit);
    EXPECT_NEAR(fit->exponent, k, kFitRoundOff);
    EXPECT_NEAR(fit->coefficient / 3e-6, 1, kFitRoundOff);
    EXPECT_EQ(fit->points, 6);
  }
}

TEST(FitPowerLaw, LeavesOutWhatALogAxisCannotHold) {
  // failed runs' costs are −1; a zero and a NaN are no measurement either
  const std::vector<double> x = {1, 2, 4, 8, 16, 0};
  const std::vector<double> y = {1, -1, 16, NAN, 256, 5};
  const auto fit = FitPowerLaw(x, y);
  ASSERT_TRUE(fit);
  EXPECT_EQ(fit->points, 3);
  EXPECT_NEAR(fit->exponent, 2, kFitRoundOff);
}

TEST(FitPowerLaw, NoFitWithoutTwoDistinctSizes) {
  EXPECT_FALSE(FitPowerLaw({}, {}));
  EXPECT_FALSE(FitPowerLaw({8}, {1e-3}));
  EXPECT_FALSE(FitPowerLaw({8, 8}, {1e-3, 2e-3}));
  EXPECT_FALSE(FitPowerLaw({8, 64}, {1e-3, -1}));
}

}  // namespace
}  // namespace ecpsim::evaluation
