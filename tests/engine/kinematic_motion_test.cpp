#include "engine/kinematic_motion.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kEps = std::numeric_limits<double>::epsilon();
// rotation-matrix entries (O(1)) a few dozen flops from their inputs, by two routes (Eigen's
// AngleAxis and slerp against the exponential map): a few ulps each
constexpr double kRotationRoundOff = 16 * kEps;
constexpr double kDegree = M_PI / 180;

const std::string kWhere = "test.yaml:3:5: bodies[1].motion";

// the angle (rad) between two orientations
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return QuaternionLog(b * a.conjugate()).norm();
}

double MatrixDistance(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return (a.toRotationMatrix() - b.toRotationMatrix()).cwiseAbs().maxCoeff();
}

Eigen::Quaterniond AboutAxis(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

PoseExpressions Expressions(const std::vector<std::string>& position,
                            const std::vector<std::string>& rpy_deg) {
  PoseExpressions e;
  for (int i = 0; i < 3; ++i) {
    e.position[i] = TimeFunction(position[i], "position");
    e.rpy_deg[i] = TimeFunction(rpy_deg[i], "rpy");
  }
  return e;
}

// ---- constant twist --------------------------------------------------------------------------

ConstantTwist SomeTwist() {
  ConstantTwist c;
  c.start.p = Eigen::Vector3d(0.3, -0.2, 0.05);
  c.start.q = RpyToQuaternion(Eigen::Vector3d(10, 20, 30) * kDegree);
  c.v = Eigen::Vector3d(0.1, -0.05, 0.02);
  c.w = Eigen::Vector3d(0.2, -0.4, 1.5);
  return c;
}

TEST(KinematicMotionTest, ConstantTwistStepTwistIsTheTwistItself) {
  const ConstantTwist c = SomeTwist();
  const KinematicMotion motion(c, kWhere);
  for (int k : {0, 7, 1000}) {
    const KinematicMotion::Twist twist = motion.StepTwist(k * 0.01, 0.01);
    EXPECT_EQ(twist.v, c.v) << "k = " << k;
    EXPECT_EQ(twist.w, c.w) << "k = " << k;
  }
}

TEST(KinematicMotionTest, ConstantTwistPoseIsTheClosedForm) {
  const ConstantTwist c = SomeTwist();
  const KinematicMotion motion(c, kWhere);
  for (double t : {0.0, 0.37, 2.5, 40.0}) {
    const KinematicPose pose = motion.PoseAt(t);
    EXPECT_EQ(pose.p, c.start.p + c.v * t) << "t = " << t;
    // R(t) = Exp(ω t) R0, the exponential by Eigen's angle-axis; ω t reaches 62 rad, whose
    // sine and cosine carry ulps of 62
    const Eigen::Quaterniond expected = AboutAxis(c.w.norm() * t, c.w) * c.start.q;
    EXPECT_LT(MatrixDistance(pose.q, expected), kRotationRoundOff * (1 + c.w.norm() * t))
        << "t = " << t;
  }
}

TEST(KinematicMotionTest, ConstantVelocityPoseAtStepEndsHasNoDrift) {
  // the pose at the end of step k is p0 + v (k h) with t = k h as the engine counts time, never
  // a running sum, at any step count
  ConstantTwist c;
  c.start.p = Eigen::Vector3d(0.1, 0.2, 0.3);
  c.start.q = RpyToQuaternion(Eigen::Vector3d(0, 0, 45) * kDegree);
  c.v = Eigen::Vector3d(0.1, -0.3, 0.7);
  const KinematicMotion motion(c, kWhere);
  const double h = 0.01;
  for (long k : {1L, 100L, 12345L, 1L << 30, 1L << 45}) {
    const double t = static_cast<double>(k) * h;
    const KinematicPose pose = motion.PoseAt(t);
    EXPECT_EQ(pose.p, c.start.p + c.v * t) << "k = " << k;
    EXPECT_LT(AngleBetween(pose.q, c.start.q), 2 * kEps) << "k = " << k;
  }
}

TEST(KinematicMotionTest, ConstantTwistRefusesAHalfTurnPerStep) {
  ConstantTwist c = SomeTwist();
  const double h = 0.01;
  c.w = Eigen::Vector3d(0, 0, M_PI / h);
  const KinematicMotion half_turn(c, kWhere);
  EXPECT_THAT(
      [&] { half_turn.StepTwist(0.5, h); },
      ThrowsMessage<InputError>(AllOf(HasSubstr(kWhere + ": the step from t = 0.5 s"),
                                      HasSubstr("h = 0.01 s"), HasSubstr("use a smaller h"))));
  c.w = Eigen::Vector3d(0, 0, 0.99 * M_PI / h);
  const KinematicMotion below(c, kWhere);
  EXPECT_EQ(below.StepTwist(0.5, h).w, c.w);
}

TEST(KinematicMotionTest, ConstantTwistRejectsBadNumbers) {
  ConstantTwist c = SomeTwist();
  c.v.y() = NAN;
  EXPECT_THAT([&] { KinematicMotion(c, kWhere); },
              ThrowsMessage<InputError>(HasSubstr(kWhere + ".velocity.linear = [0.1, nan, 0.02]")));
  c = SomeTwist();
  c.start.q = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_THAT([&] { KinematicMotion(c, kWhere); },
              ThrowsMessage<InputError>(HasSubstr("expected a non-zero quaternion")));
}

// ---- expressions -----------------------------------------------------------------------------

// a point on a circle of radius r at Ω rad/s, turning with it (yaw Ω t, given in degrees)
constexpr double kRadius = 0.3;   // m
constexpr double kOmega = 2;      // rad/s
constexpr double kHeight = 0.05;  // m
constexpr double kStep = 0.01;    // s

KinematicMotion Circle() {
  return KinematicMotion(
      Expressions({"0.3*cos(2*t)", "0.3*sin(2*t)", "0.05"}, {"0", "0", "180/pi*2*t"}), kWhere);
}

TEST(KinematicMotionTest, CircleStepVelocityIsTheChord) {
  const KinematicMotion motion = Circle();
  // each of the four coordinates is r·cos or r·sin to within 2 ulps of r (muparser and libm
  // alike), so the chord's difference carries at most 8 ε r, divided by h
  const double chord_tolerance = 8 * kEps * kRadius / kStep;  // m/s
  for (int k : {0, 1, 57, 999}) {
    const double t = k * kStep;
    const KinematicMotion::Twist twist = motion.StepTwist(t, kStep);
    const double a = kOmega * t;
    const double b = kOmega * (t + kStep);
    const Eigen::Vector3d chord(kRadius * (std::cos(b) - std::cos(a)),
                                kRadius * (std::sin(b) - std::sin(a)), 0);
    EXPECT_LT((twist.v - chord / kStep).norm(), chord_tolerance) << "k = " << k;
    // the yaw Ω t, through degrees and back, carries ulps of Ω t at both ends
    const double turn_tolerance = 8 * kEps * (1 + kOmega * (t + kStep)) / kStep;  // rad/s
    EXPECT_LT((twist.w - Eigen::Vector3d(0, 0, kOmega)).norm(), turn_tolerance) << "k = " << k;
  }
}

// the engine's update c⁺ = c + h v, Q⁺ = Exp(h ω) Q with StepTwist's (v, ω), from PoseAt(0),
// stays on PoseAt(k h) at every step up to the round-off of its own sums
void ExpectEngineUpdateFollowsPoses(const KinematicMotion& motion, int steps, double h,
                                    double size) {
  KinematicPose integrated = motion.PoseAt(0);
  for (int k = 0; k < steps; ++k) {
    const KinematicMotion::Twist twist = motion.StepTwist(k * h, h);
    integrated.p += h * twist.v;
    integrated.q = IntegrateOrientation(integrated.q, twist.w, h);
    const KinematicPose prescribed = motion.PoseAt((k + 1) * h);
    // each step rounds h v against the chord (2 ε of a step's travel) and the sum (ε |c|), and
    // t + h differs from (k + 1) h by an ulp of t: a few ε of the size per step
    const double position_tolerance = 4 * kEps * size * (k + 2);  // m
    // each step composes four rounded quaternion products, Exp and Log: a few ε per step
    const double angle_tolerance = 16 * kEps * (k + 2);  // rad
    ASSERT_LT((integrated.p - prescribed.p).norm(), position_tolerance) << "step " << k;
    ASSERT_LT(AngleBetween(integrated.q, prescribed.q), angle_tolerance) << "step " << k;
  }
}

TEST(KinematicMotionTest, EngineUpdateReproducesTheCircleWithoutDrift) {
  // a drifting twist (the derivative r Ω (−sin, cos) instead of the chord) would leave the
  // circle by r Ω² h² / 2 per step, 0.06 m over these 1000 steps
  ExpectEngineUpdateFollowsPoses(Circle(), 1000, kStep, std::hypot(kRadius, kHeight));
}

TEST(KinematicMotionTest, EngineUpdateReproducesATumbleWithoutDrift) {
  // all three angles moving, so the rotation axis turns from step to step
  const KinematicMotion tumble(
      Expressions({"0.2*t", "0.1*sin(3*t)", "0.05+0.02*t*t"}, {"20*sin(t)", "10*t", "30*cos(2*t)"}),
      kWhere);
  ExpectEngineUpdateFollowsPoses(tumble, 1000, kStep, 3.0);  // |p| ≤ 2.9 m up to t = 10 s

  PoseExpressions e = Expressions({"0", "0", "0"}, {"0", "0", "0"});
  e.orientation = PoseExpressions::Orientation::kAxisAngle;
  e.axis = Eigen::Vector3d(1, 2, 2);
  e.angle = TimeFunction("0.5*t+0.3*sin(3*t)", "angle");
  ExpectEngineUpdateFollowsPoses(KinematicMotion(e, kWhere), 1000, kStep, 1.0);
}

TEST(KinematicMotionTest, AxisAngleIsATurnAboutTheNormalizedAxis) {
  PoseExpressions e = Expressions({"1", "2", "3"}, {"0", "0", "0"});
  e.orientation = PoseExpressions::Orientation::kAxisAngle;
  e.axis = Eigen::Vector3d(0, 3, 4);
  e.angle = TimeFunction("1.5*t", "angle");
  const KinematicMotion motion(e, kWhere);
  const KinematicPose pose = motion.PoseAt(0.8);
  EXPECT_EQ(pose.p, Eigen::Vector3d(1, 2, 3));
  EXPECT_LT(MatrixDistance(pose.q, AboutAxis(1.2, Eigen::Vector3d(0, 0.6, 0.8))),
            kRotationRoundOff);
  // a turn at a constant rate about a fixed axis: ω = 1.5 rad/s along it, to the round-off of
  // the angle (ulps of 1.2 rad) over h
  const KinematicMotion::Twist twist = motion.StepTwist(0.8, kStep);
  EXPECT_LT((twist.w - 1.5 * Eigen::Vector3d(0, 0.6, 0.8)).norm(), 8 * kEps * 2 / kStep);
  EXPECT_EQ(twist.v, Eigen::Vector3d::Zero());
}

TEST(KinematicMotionTest, ExpressionsRefuseAStepOfHalfATurnOrMore) {
  // yaw 360°/s: 0.45 s turn 0.9 π (fine); 0.5 s exactly π; 0.6 s turn 1.2 π, whose chord is
  // 0.8 π the other way round; 1 s a whole turn, whose chord is no turn at all
  const KinematicMotion spin(Expressions({"0", "0", "0"}, {"0", "0", "360*t"}), kWhere);
  const KinematicMotion::Twist fine = spin.StepTwist(0, 0.45);
  EXPECT_NEAR(fine.w.z(), 2 * M_PI, 8 * kEps * M_PI / 0.45);
  for (double h : {0.5, 0.6, 1.0}) {
    EXPECT_THAT([&] { spin.StepTwist(0, h); },
                ThrowsMessage<InputError>(AllOf(HasSubstr(kWhere + ": the step from t = 0 s"),
                                                HasSubstr(fmt::format("h = {} s", h)),
                                                HasSubstr("expected a turn below π per step"))))
        << "h = " << h;
  }
}

TEST(KinematicMotionTest, ExpressionsReportNonFiniteAndHugeValues) {
  const KinematicMotion pole(Expressions({"1/(t-1)", "0", "0"}, {"0", "0", "0"}), kWhere);
  EXPECT_THAT([&] { pole.PoseAt(1); }, ThrowsMessage<InputError>(HasSubstr("at t = 1 s")));
  // the step's midpoint meets the pole
  EXPECT_THAT([&] { pole.StepTwist(0.995, 0.01); },
              ThrowsMessage<InputError>(HasSubstr("at t = 1 s")));
  const KinematicMotion far(Expressions({"1e200*t", "0", "0"}, {"0", "0", "0"}), kWhere);
  EXPECT_THAT([&] { far.PoseAt(1); },
              ThrowsMessage<InputError>(
                  HasSubstr(kWhere + ": the position at t = 1 s is [1e+200, 0, 0] m")));
}

TEST(KinematicMotionTest, ExpressionsRejectAZeroAxis) {
  PoseExpressions e = Expressions({"0", "0", "0"}, {"0", "0", "0"});
  e.orientation = PoseExpressions::Orientation::kAxisAngle;
  e.axis = Eigen::Vector3d::Zero();
  EXPECT_THAT([&] { KinematicMotion(e, kWhere); },
              ThrowsMessage<InputError>(HasSubstr(
                  kWhere + ".expressions.axis_angle.axis = [0, 0, 0]: expected a non-zero axis")));
}

// ---- waypoints -------------------------------------------------------------------------------

std::vector<Waypoint> ThreeWaypoints() {
  return {{1, {Eigen::Vector3d(0, 0, 0.1), Eigen::Quaterniond::Identity()}},
          {3, {Eigen::Vector3d(0.4, 0.2, 0.1), AboutAxis(M_PI / 2, Eigen::Vector3d::UnitZ())}},
          {4,
           {Eigen::Vector3d(0.4, 0.6, 0.3), AboutAxis(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                                AboutAxis(M_PI / 3, Eigen::Vector3d::UnitX())}}};
}

TEST(KinematicMotionTest, WaypointsAreMetExactly) {
  const std::vector<Waypoint> waypoints = ThreeWaypoints();
  const KinematicMotion motion(waypoints, kWhere);
  for (const Waypoint& w : waypoints) {
    const KinematicPose pose = motion.PoseAt(w.t);
    EXPECT_EQ(pose.p, w.pose.p) << "t = " << w.t;
    EXPECT_LT(MatrixDistance(pose.q, w.pose.q), kRotationRoundOff) << "t = " << w.t;
  }
}

TEST(KinematicMotionTest, WaypointsInterpolateLinearlyAndBySlerp) {
  const std::vector<Waypoint> waypoints = ThreeWaypoints();
  const KinematicMotion motion(waypoints, kWhere);
  for (double t : {1.5, 2.2, 3.7}) {
    const size_t i = t < 3 ? 0 : 1;
    const Waypoint& a = waypoints[i];
    const Waypoint& b = waypoints[i + 1];
    const double s = (t - a.t) / (b.t - a.t);
    const KinematicPose pose = motion.PoseAt(t);
    // O(1) coordinates a few flops from the waypoints
    EXPECT_LT((pose.p - (a.pose.p + s * (b.pose.p - a.pose.p))).norm(), 4 * kEps) << "t = " << t;
    EXPECT_LT(MatrixDistance(pose.q, a.pose.q.slerp(s, b.pose.q)), kRotationRoundOff)
        << "t = " << t;
  }
  // 1.5 s is a quarter of the first segment: a quarter of its 90° yaw
  EXPECT_LT(MatrixDistance(motion.PoseAt(1.5).q, AboutAxis(M_PI / 8, Eigen::Vector3d::UnitZ())),
            kRotationRoundOff);
}

TEST(KinematicMotionTest, WaypointsHoldBeforeTheFirstAndAfterTheLast) {
  const std::vector<Waypoint> waypoints = ThreeWaypoints();
  const KinematicMotion motion(waypoints, kWhere);
  for (double t : {-5.0, 0.0, 1.0}) {
    EXPECT_EQ(motion.PoseAt(t).p, waypoints.front().pose.p);
    EXPECT_EQ(motion.PoseAt(t).q.coeffs(), waypoints.front().pose.q.coeffs());
  }
  for (double t : {4.0, 4.5, 100.0}) {
    EXPECT_EQ(motion.PoseAt(t).p, waypoints.back().pose.p);
    EXPECT_LT(MatrixDistance(motion.PoseAt(t).q, waypoints.back().pose.q), kRotationRoundOff);
  }
  // holding still: no twist at all
  for (double t : {-5.0, 0.0, 4.0, 100.0}) {
    const KinematicMotion::Twist twist = motion.StepTwist(t, kStep);
    EXPECT_EQ(twist.v, Eigen::Vector3d::Zero()) << "t = " << t;
    EXPECT_EQ(twist.w, Eigen::Vector3d::Zero()) << "t = " << t;
  }
}

TEST(KinematicMotionTest, WaypointSegmentIsOneConstantTwist) {
  const std::vector<Waypoint> waypoints = ThreeWaypoints();
  const KinematicMotion motion(waypoints, kWhere);
  // the first segment: (0.4, 0.2, 0) m and 90° about z in 2 s
  const Eigen::Vector3d v(0.2, 0.1, 0);
  const Eigen::Vector3d w(0, 0, M_PI / 4);
  for (double t : {1.0, 1.5, 2.99}) {
    const KinematicMotion::Twist twist = motion.StepTwist(t, kStep);
    // the chord of O(1) coordinates over h: ulps of 1 m per 0.01 s
    EXPECT_LT((twist.v - v).norm(), 8 * kEps / kStep) << "t = " << t;
    EXPECT_LT((twist.w - w).norm(), 8 * kEps / kStep) << "t = " << t;
  }
  // a step across the waypoint at 3 s: the chord from the first segment's pose to the second's
  const double t = 2.995;
  const Eigen::Vector3d from =
      waypoints[0].pose.p + (1.995 / 2) * (waypoints[1].pose.p - waypoints[0].pose.p);
  const Eigen::Vector3d to =
      waypoints[1].pose.p + 0.005 * (waypoints[2].pose.p - waypoints[1].pose.p);
  EXPECT_LT((motion.StepTwist(t, kStep).v - (to - from) / kStep).norm(), 8 * kEps / kStep);
}

TEST(KinematicMotionTest, SlerpTakesTheShortestArc) {
  // 270° about z is −90°: the motion turns backwards, whatever the sign of the quaternion
  const Eigen::Quaterniond q270 = AboutAxis(1.5 * M_PI, Eigen::Vector3d::UnitZ());
  for (const Eigen::Quaterniond& end : {q270, Eigen::Quaterniond(-q270.coeffs())}) {
    const KinematicMotion motion(
        std::vector<Waypoint>{{0, {Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()}},
                              {1, {Eigen::Vector3d::Zero(), end}}},
        kWhere);
    EXPECT_LT(MatrixDistance(motion.PoseAt(0.5).q, AboutAxis(-M_PI / 4, Eigen::Vector3d::UnitZ())),
              kRotationRoundOff);
    EXPECT_NEAR(motion.StepTwist(0.2, kStep).w.z(), -M_PI / 2, 8 * kEps / kStep);
  }
}

TEST(KinematicMotionTest, WaypointsAreValidated) {
  const auto throws = [](std::vector<Waypoint> waypoints, const std::string& message) {
    EXPECT_THAT([&] { KinematicMotion(waypoints, kWhere); },
                ThrowsMessage<InputError>(HasSubstr(message)));
  };
  throws({}, kWhere + ".waypoints = []: expected a list of at least one waypoint");
  std::vector<Waypoint> w = ThreeWaypoints();
  w[2].t = 3;
  throws(w, kWhere + ".waypoints[2].t = 3: expected a time > 3 s, waypoint 1's");
  w = ThreeWaypoints();
  w[1].pose.p.x() = INFINITY;
  throws(w, kWhere + ".waypoints[1].position = [inf, 0.2, 0.1]: expected finite numbers");
  w = ThreeWaypoints();
  w[0].pose.q = Eigen::Quaterniond(0, 0, 0, 0);
  throws(w, kWhere + ".waypoints[0].quaternion = [0, 0, 0, 0]: expected a non-zero quaternion");
  // 0° then 180° about z: which way round is undefined
  w = ThreeWaypoints();
  w[1].pose.q = AboutAxis(M_PI, Eigen::Vector3d::UnitZ());
  throws(w, kWhere + ".waypoints[1]: its orientation is 3.14159265 rad from waypoint 0's");
}

TEST(KinematicMotionTest, WaypointStepTurningPastHalfATurnIsRefused) {
  // two segments of 120° each within one step: 240° in the step, its chord −120°
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const KinematicMotion motion(
      std::vector<Waypoint>{{0, {Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()}},
                            {0.005, {Eigen::Vector3d::Zero(), AboutAxis(2 * M_PI / 3, z)}},
                            {0.01, {Eigen::Vector3d::Zero(), AboutAxis(4 * M_PI / 3, z)}}},
      kWhere);
  EXPECT_THAT([&] { motion.StepTwist(0, kStep); },
              ThrowsMessage<InputError>(HasSubstr("its orientation at mid-step")));
}

}  // namespace
}  // namespace ecpsim::engine
