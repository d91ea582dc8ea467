// The predicted start's trend (engine/models/solution_trend.h): exact for a point quadratic in
// time, kept only across steps of one length.

#include "engine/models/solution_trend.h"

#include <optional>

#include <gtest/gtest.h>

namespace ecpsim::engine {
namespace {

using Point = SolutionTrend::Point;

// a point z(t) = a + b t + c t² with entries of every sign and size
Point QuadraticAt(double t) {
  Point z;
  for (int i = 0; i < SolutionTrend::kSize; ++i) {
    const double a = 0.3 * (i - 7), b = 1.5 - 0.2 * i, c = (i % 3 - 1) * 4.0;
    z[i] = a + b * t + c * t * t;
  }
  return z;
}

// the trend after steps of length h ending at t = 0, h, …, (steps − 1) h
SolutionTrend TrendOver(int steps, double h) {
  SolutionTrend trend = NextTrend(nullptr, Point::Zero(), QuadraticAt(0), h);
  for (int i = 1; i < steps; ++i)
    trend = NextTrend(&trend, QuadraticAt((i - 1) * h), QuadraticAt(i * h), h);
  return trend;
}

TEST(SolutionTrendTest, APointQuadraticInTimeIsPredictedExactly) {
  constexpr double h = 0.01;
  const SolutionTrend trend = TrendOver(3, h);
  ASSERT_EQ(trend.steps, 2);
  const std::optional<Point> predicted = PredictPoint(trend, QuadraticAt(2 * h), h);
  ASSERT_TRUE(predicted.has_value());
  // the differences of a quadratic are exact up to the round-off of entries of size ≤ 3
  constexpr double kRoundOff = 1e-14;
  EXPECT_LE((*predicted - QuadraticAt(3 * h)).cwiseAbs().maxCoeff(), kRoundOff);
}

TEST(SolutionTrendTest, TwoDifferencesAreNeededBeforeAPrediction) {
  constexpr double h = 0.01;
  // the first point ends a step without a trend before it: no difference yet
  EXPECT_EQ(TrendOver(1, h).steps, 0);
  EXPECT_EQ(TrendOver(2, h).steps, 1);
  EXPECT_FALSE(PredictPoint(TrendOver(1, h), QuadraticAt(0), h).has_value());
  EXPECT_FALSE(PredictPoint(TrendOver(2, h), QuadraticAt(h), h).has_value());
  EXPECT_TRUE(PredictPoint(TrendOver(3, h), QuadraticAt(2 * h), h).has_value());
}

TEST(SolutionTrendTest, AStepOfAnotherLengthStartsTheTrendAfresh) {
  constexpr double h = 0.01;
  const SolutionTrend trend = TrendOver(3, h);
  // the driver's sub-steps of h/2: their impulses are half a step's, so no difference spans them
  const SolutionTrend half = NextTrend(&trend, QuadraticAt(2 * h), QuadraticAt(2.5 * h), h / 2);
  EXPECT_EQ(half.steps, 0);
  EXPECT_FALSE(PredictPoint(half, QuadraticAt(2.5 * h), h / 2).has_value());
  // nor is a trend of steps of h used for a step of h/2
  EXPECT_FALSE(PredictPoint(trend, QuadraticAt(2 * h), h / 2).has_value());
}

}  // namespace
}  // namespace ecpsim::engine
