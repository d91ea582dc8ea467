#include "engine/loads.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

using Vector6d = Eigen::Matrix<double, 6, 1>;

// one or two roundings of a few flops: the values below are O(10), so 1e-13 is a few ulps
constexpr double kTight = 1e-13;

TEST(TimeFunctionTest, EvaluatesThePaperDeskForce) {
  const TimeFunction f("22.5*sin(2*pi*t)+22.5", "desk.yaml:3:5: loads[0].force[0]");
  EXPECT_NEAR(f(0), 22.5, kTight);
  EXPECT_NEAR(f(0.25), 45, kTight);
  EXPECT_NEAR(f(0.75), 0, kTight);
  EXPECT_NEAR(f(0.1), 22.5 * std::sin(2 * M_PI * 0.1) + 22.5, kTight);
  EXPECT_EQ(f.expression(), "22.5*sin(2*pi*t)+22.5");
}

TEST(TimeFunctionTest, PiIsTheDoubleClosestToPi) { EXPECT_EQ(TimeFunction("pi", "here")(0), M_PI); }

TEST(TimeFunctionTest, ConstantIgnoresTime) {
  const TimeFunction c(3.5);
  EXPECT_EQ(c(0), 3.5);
  EXPECT_EQ(c(1e6), 3.5);
  EXPECT_EQ(TimeFunction()(2), 0);
}

TEST(TimeFunctionTest, CopiesEvaluateIndependentlyOfTheOriginal) {
  const TimeFunction f("2*t+1", "here");
  TimeFunction g(0.0);
  g = f;
  const TimeFunction h(f);
  EXPECT_EQ(f(1), 3);
  EXPECT_EQ(g(2), 5);
  EXPECT_EQ(h(3), 7);
  // the shared parser holds no stale t between calls
  EXPECT_EQ(f(0), 1);
}

TEST(TimeFunctionTest, ARecompiledCopyIsTheSameFunctionWithItsOwnMessages) {
  const TimeFunction f("1/(t-1)", "s.yaml:9:3: loads[0].force[0]");
  const TimeFunction own = f.Recompiled();
  for (const double t : {0.0, 0.25, 2.0, 1e3}) EXPECT_EQ(own(t), f(t));
  EXPECT_EQ(own.expression(), f.expression());
  EXPECT_THAT([&] { own(1); }, ThrowsMessage<InputError>(HasSubstr("s.yaml:9:3")));
  EXPECT_EQ(TimeFunction(2.5).Recompiled()(7), 2.5);
}

TEST(TimeFunctionTest, SyntaxErrorNamesWhereExpressionAndMuparserMessage) {
  EXPECT_THAT([] { TimeFunction("2*(t", "s.yaml:4:7: loads[1].torque[2]"); },
              ThrowsMessage<InputError>(AllOf(
                  HasSubstr("s.yaml:4:7: loads[1].torque[2]"), HasSubstr("\"2*(t\""),
                  HasSubstr("Missing parenthesis"), HasSubstr("expected an expression of t"))));
}

TEST(TimeFunctionTest, UnknownVariableIsAnError) {
  EXPECT_THAT([] { TimeFunction("3*x+t", "s.yaml:2:1: f"); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr("s.yaml:2:1: f"), HasSubstr("\"3*x+t\""), HasSubstr("\"x\""))));
}

TEST(TimeFunctionTest, EmptyAndMultipleResultsAreErrors) {
  EXPECT_THROW(TimeFunction("", "here"), InputError);
  EXPECT_THAT([] { TimeFunction("1, 2", "here"); },
              ThrowsMessage<InputError>(HasSubstr("2 comma-separated results")));
}

TEST(TimeFunctionTest, NonFiniteValueIsAnErrorAtThatTime) {
  const TimeFunction f("1/(t-1)", "s.yaml:9:3: loads[0].force[0]");
  EXPECT_EQ(f(0), -1);
  EXPECT_THAT([&] { f(1); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("s.yaml:9:3: loads[0].force[0]"),
                                              HasSubstr("at t = 1 s"), HasSubstr("inf"),
                                              HasSubstr("expected a finite value"))));
  const TimeFunction g("sqrt(t-2)", "here");
  EXPECT_THROW(g(0), InputError);
  EXPECT_THROW(TimeFunction(std::nan("")), InputError);
}

Load ConstantForce(int body, const Eigen::Vector3d& f, double start, double end) {
  Load load;
  load.body = body;
  load.x = TimeFunction(f.x());
  load.y = TimeFunction(f.y());
  load.z = TimeFunction(f.z());
  load.start = start;
  load.end = end;
  return load;
}

TEST(AppliedImpulseTest, ForceIsActiveOnTheHalfOpenWindow) {
  const std::vector<Load> loads = {ConstantForce(0, {1, 2, 3}, 0.25, 0.5)};
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double h = 0.125;  // a power of two: t values and h·F are exact
  Vector6d expected;
  expected << 0.125, 0.25, 0.375, 0, 0, 0;
  EXPECT_EQ(AppliedImpulse(loads, {}, 0, 0.125, h, I), Vector6d::Zero());
  EXPECT_EQ(AppliedImpulse(loads, {}, 0, 0.25, h, I), expected);
  EXPECT_EQ(AppliedImpulse(loads, {}, 0, 0.375, h, I), expected);
  EXPECT_EQ(AppliedImpulse(loads, {}, 0, 0.5, h, I), Vector6d::Zero());
  // another body's load does not act
  EXPECT_EQ(AppliedImpulse(loads, {}, 1, 0.25, h, I), Vector6d::Zero());
}

TEST(AppliedImpulseTest, WindowInsideAStepActsForItsOverlap) {
  // a window [0.3, 0.35) inside the step [0.25, 0.375): the impulse of 0.05 s, not a whole step
  // or nothing; sampled at the window's start
  const std::vector<Load> loads = {ConstantForce(0, {8, 0, 0}, 0.3, 0.35)};
  const auto p = AppliedImpulse(loads, {}, 0, 0.25, 0.125, Eigen::Matrix3d::Identity());
  EXPECT_NEAR(p[0], 8 * 0.05, kTight);
}

TEST(AppliedImpulseTest, WindowOnAStepBoundaryIsInsensitiveToRoundOffInTime) {
  // the T-bar's 2.5 s window start with h = 0.01: t after 250 steps is 2.5 only up to round-off,
  // and either side of it the step gets the load's impulse up to that round-off (earlier, a
  // whole step's impulse hung on the last bit of t)
  const std::vector<Load> loads = {ConstantForce(0, {1, 0, 0}, 2.5, 2.64)};
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double h = 0.01;
  const double below = std::nextafter(2.5, 0.0), above = std::nextafter(2.5, 3.0);
  const double at_below = AppliedImpulse(loads, {}, 0, below, h, I)[0];
  const double at_above = AppliedImpulse(loads, {}, 0, above, h, I)[0];
  // N·s: 1 N over a few ulps of t ≈ 2.5 s (one ulp is 4.4e-16 s)
  constexpr double kTimeSliver = 1e-15;
  EXPECT_NEAR(at_below, h, kTimeSliver);
  EXPECT_NEAR(at_above, h, kTimeSliver);
  // the step before: at most a round-off sliver
  EXPECT_LE(AppliedImpulse(loads, {}, 0, below - h, h, I)[0], kTimeSliver);
  // marched as a stepper does, the window's total impulse is 1 N × 0.14 s
  double total = 0;
  for (double t = 0; t < 3; t += h) total += AppliedImpulse(loads, {}, 0, t, h, I)[0];
  // N·s: the marched t drifts by round-off over its 300 additions of h, and the sum with it
  constexpr double kMarchedRoundOff = 1e-12;
  EXPECT_NEAR(total, 0.14, kMarchedRoundOff);
}

TEST(AppliedImpulseTest, ImpulseOnAStepBoundaryLandsInTheStepStartingThere) {
  // 0.5 s with h = 0.01: step 50, whichever side of 0.5 the marched t lies
  Impulse impulse;
  impulse.time = 0.5;
  impulse.linear = Eigen::Vector3d(1, 0, 0);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (const double t : {std::nextafter(0.5, 0.0), 0.5, std::nextafter(0.5, 1.0)}) {
    EXPECT_EQ(AppliedImpulse({}, {impulse}, 0, t, 0.01, I)[0], 1) << t;
    EXPECT_EQ(AppliedImpulse({}, {impulse}, 0, t - 0.01, 0.01, I)[0], 0) << t;
  }
}

TEST(AppliedImpulseTest, TimeDependentForceIsSampledAtTheStartOfTheStep) {
  Load load;
  load.x = TimeFunction("22.5*sin(2*pi*t)+22.5", "here");
  load.y = TimeFunction("22.5*cos(2*pi*t)+22.5", "here");
  const double t = 0.3, h = 0.01;
  const auto p = AppliedImpulse({load}, {}, 0, t, h, Eigen::Matrix3d::Identity());
  EXPECT_NEAR(p[0], h * (22.5 * std::sin(2 * M_PI * t) + 22.5), kTight);
  EXPECT_NEAR(p[1], h * (22.5 * std::cos(2 * M_PI * t) + 22.5), kTight);
  EXPECT_EQ(p.tail<4>(), Eigen::Vector4d::Zero());
}

TEST(AppliedImpulseTest, TorqueAddsOnlyAngularImpulse) {
  Load torque = ConstantForce(0, {0, 0, 2}, 0, 1e300);
  torque.kind = Load::Kind::kTorque;
  const auto p = AppliedImpulse({torque}, {}, 0, 0, 0.5, Eigen::Matrix3d::Identity());
  Vector6d expected;
  expected << 0, 0, 0, 0, 0, 1;
  EXPECT_EQ(p, expected);
}

TEST(AppliedImpulseTest, PointForceAddsRotatedLeverArmTorque) {
  // F = (0, 0, 10) N at the body point (1, 0, 0) m; the body is turned 90° about z, so the
  // lever arm is R·p_B = (0, 1, 0) m and the torque impulse is h·(r × F) = 0.5·(10, 0, 0)
  Load load = ConstantForce(0, {0, 0, 10}, 0, 1e300);
  load.at_point = true;
  load.point_B = Eigen::Vector3d(1, 0, 0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
  const auto p = AppliedImpulse({load}, {}, 0, 0, 0.5, R);
  EXPECT_NEAR(p[0], 0, kTight);
  EXPECT_NEAR(p[1], 0, kTight);
  EXPECT_NEAR(p[2], 5, kTight);
  EXPECT_NEAR(p[3], 5, kTight);
  EXPECT_NEAR(p[4], 0, kTight);
  EXPECT_NEAR(p[5], 0, kTight);
}

TEST(AppliedImpulseTest, EachImpulseIsAppliedExactlyOnce) {
  // times on the step grid (0.3 = 30 h is not exactly representable), between grid points,
  // at 0 and at the very end of the marched interval
  std::vector<Impulse> impulses;
  const double times[] = {0, 0.3, 0.5, 0.555, 0.7, 0.99};
  for (int i = 0; i < 6; ++i) {
    Impulse impulse;
    impulse.time = times[i];
    impulse.linear = Eigen::Vector3d(std::ldexp(1.0, i), 0, 0);  // bit i marks impulse i
    impulses.push_back(impulse);
  }
  for (double h : {0.01, 0.1 / 3, 0.001}) {
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    int steps_with_impulse = 0;
    // t advances as a stepper does: t ← t + h
    for (double t = 0; t < 1; t += h) {
      const auto p = AppliedImpulse({}, impulses, 0, t, h, Eigen::Matrix3d::Identity());
      total += p.head<3>();
      steps_with_impulse += p[0] != 0 ? 1 : 0;
    }
    EXPECT_EQ(total.x(), 63) << "h = " << h;  // 1 + 2 + ... + 32, each once
    EXPECT_EQ(steps_with_impulse, 6) << "h = " << h;
  }
}

TEST(AppliedImpulseTest, ImpulseAtAPointAddsItsMoment) {
  Impulse impulse;
  impulse.body = 1;
  impulse.time = 0.25;
  impulse.linear = Eigen::Vector3d(0, 2, 0);
  impulse.angular = Eigen::Vector3d(0, 0, 0.5);
  impulse.at_point = true;
  impulse.point_B = Eigen::Vector3d(0.5, 0, 0);
  // r × J = (0.5, 0, 0) × (0, 2, 0) = (0, 0, 1), plus the pure angular 0.5
  const auto p = AppliedImpulse({}, {impulse}, 1, 0.25, 0.01, Eigen::Matrix3d::Identity());
  Vector6d expected;
  expected << 0, 2, 0, 0, 0, 1.5;
  EXPECT_EQ(p, expected);
  EXPECT_EQ(AppliedImpulse({}, {impulse}, 0, 0.25, 0.01, Eigen::Matrix3d::Identity()),
            Vector6d::Zero());
  EXPECT_EQ(AppliedImpulse({}, {impulse}, 1, 0.26, 0.01, Eigen::Matrix3d::Identity()),
            Vector6d::Zero());
}

}  // namespace
}  // namespace ecpsim::engine
