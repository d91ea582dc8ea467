#include "engine/kinematic_motion.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/rotation.h"
#include "engine/scene_limits.h"

namespace ecpsim::engine {
namespace {

// a quaternion shorter than this carries no direction to normalize (and is surely a typo), as
// the scene loader's
constexpr double kMinQuaternionNorm = 1e-9;
// rad: a motion resolved by the step puts its orientation at mid-step within O(h²) of the
// constant turn between the step's ends; one that turns past π in the step wraps that chord the
// other way round, π away from the true midpoint (about a fixed axis): the threshold halfway
constexpr double kMaxMidpointDeviation = M_PI / 2;

std::string ShowNumbers(const double* x, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i) out += fmt::format("{}{}", i == 0 ? "" : ", ", x[i]);
  return out + "]";
}

// every number finite and within ±1e150, the format's range for any number
void CheckNumbers(const std::string& what, const double* x, int n, const std::string& unit) {
  for (int i = 0; i < n; ++i) {
    if (!OutOfMagnitude(x[i]).empty()) {
      throw InputError(fmt::format("{} = {}: expected finite numbers within ±{:g} ({})", what,
                                   ShowNumbers(x, n), kMaxMagnitude, unit));
    }
  }
}

void CheckVector(const std::string& what, const Eigen::Vector3d& x, const std::string& unit) {
  CheckNumbers(what, x.data(), 3, unit);
}

// the unit quaternion of a finite, non-zero `q`
Eigen::Quaterniond UnitQuaternion(const std::string& what, const Eigen::Quaterniond& q) {
  const Eigen::Vector4d wxyz(q.w(), q.x(), q.y(), q.z());
  CheckNumbers(what, wxyz.data(), 4, "a quaternion [w, x, y, z]");
  if (!(wxyz.norm() >= kMinQuaternionNorm)) {
    throw InputError(
        fmt::format("{} = {}: expected a non-zero quaternion [w, x, y, z] (it is "
                    "normalized)",
                    what, ShowNumbers(wxyz.data(), 4)));
  }
  return q.normalized();
}

// the turn from orientation `from` to `to`, rad in [0, π]
double Turn(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to) {
  return QuaternionLog(to * from.conjugate()).norm();
}

KinematicPose Evaluate(const PoseExpressions& e, double t) {
  KinematicPose pose;
  pose.p = Eigen::Vector3d(e.position[0](t), e.position[1](t), e.position[2](t));
  if (e.orientation == PoseExpressions::Orientation::kRpy) {
    const Eigen::Vector3d rpy_deg(e.rpy_deg[0](t), e.rpy_deg[1](t), e.rpy_deg[2](t));
    pose.q = RpyToQuaternion(rpy_deg * (M_PI / 180));
  } else {
    pose.q = QuaternionExp(e.angle(t) * e.axis);
  }
  return pose;
}

// holds the first pose before the first waypoint and the last after the last; in between, the
// segment's constant twist: position (1 − s) p0 + s p1 (exact at both ends), orientation
// Exp(s φ) q0 with φ = Log(q1 q0*), the slerp along the shortest arc
KinematicPose Interpolate(const std::vector<Waypoint>& waypoints, double t) {
  if (t <= waypoints.front().t) return waypoints.front().pose;
  if (t >= waypoints.back().t) return waypoints.back().pose;
  const auto next = std::upper_bound(waypoints.begin(), waypoints.end(), t,
                                     [](double time, const Waypoint& w) { return time < w.t; });
  const Waypoint& a = *(next - 1);
  const Waypoint& b = *next;
  const double s = (t - a.t) / (b.t - a.t);
  KinematicPose pose;
  pose.p = (1 - s) * a.pose.p + s * b.pose.p;
  const Eigen::Vector3d phi = QuaternionLog(b.pose.q * a.pose.q.conjugate());
  pose.q = (QuaternionExp(s * phi) * a.pose.q).normalized();
  return pose;
}

KinematicPose AtConstantTwist(const ConstantTwist& c, double t) {
  KinematicPose pose;
  pose.p = c.start.p + c.v * t;
  pose.q = (QuaternionExp(c.w * t) * c.start.q).normalized();
  return pose;
}

}  // namespace

KinematicMotion::KinematicMotion(PoseExpressions expressions, std::string where)
    : where_(std::move(where)) {
  if (expressions.orientation == PoseExpressions::Orientation::kAxisAngle) {
    const std::string what = where_ + ".expressions.axis_angle.axis";
    CheckVector(what, expressions.axis, "a direction, world frame");
    if (!(expressions.axis.norm() >= kMinRotationAxisLength)) {
      throw InputError(fmt::format("{} = {}: expected a non-zero axis (it is normalized)", what,
                                   ShowNumbers(expressions.axis.data(), 3)));
    }
    expressions.axis.normalize();
  }
  form_ = std::move(expressions);
}

KinematicMotion::KinematicMotion(std::vector<Waypoint> waypoints, std::string where)
    : where_(std::move(where)) {
  if (waypoints.empty()) {
    throw InputError(
        fmt::format("{}.waypoints = []: expected a list of at least one waypoint "
                    "{{t, position, orientation}}",
                    where_));
  }
  for (size_t i = 0; i < waypoints.size(); ++i) {
    Waypoint& w = waypoints[i];
    const std::string at = fmt::format("{}.waypoints[{}]", where_, i);
    CheckNumbers(at + ".t", &w.t, 1, "s");
    CheckVector(at + ".position", w.pose.p, "m, world frame");
    w.pose.q = UnitQuaternion(at + ".quaternion", w.pose.q);
    if (i == 0) continue;
    const Waypoint& previous = waypoints[i - 1];
    if (!(w.t > previous.t)) {
      throw InputError(
          fmt::format("{}.t = {}: expected a time > {} s, waypoint {}'s (strictly "
                      "increasing)",
                      at, w.t, previous.t, i - 1));
    }
    const double turn = Turn(previous.pose.q, w.pose.q);
    if (turn >= kMaxKinematicTurn) {
      throw InputError(fmt::format(
          "{}: its orientation is {:.9g} rad from waypoint {}'s: expected a turn below π "
          "between consecutive waypoints (at π the shortest arc has no direction); add a "
          "waypoint in between",
          at, turn, i - 1));
    }
  }
  form_ = std::move(waypoints);
}

KinematicMotion::KinematicMotion(ConstantTwist twist, std::string where)
    : where_(std::move(where)) {
  const std::string at = where_ + ".velocity";
  CheckVector(at + ".position", twist.start.p, "m, world frame");
  twist.start.q = UnitQuaternion(at + ".quaternion", twist.start.q);
  CheckVector(at + ".linear", twist.v, "m/s, world frame");
  CheckVector(at + ".angular", twist.w, "rad/s, world frame");
  form_ = std::move(twist);
}

KinematicPose KinematicMotion::PoseAt(double t) const {
  KinematicPose pose;
  if (const auto* expressions = std::get_if<PoseExpressions>(&form_)) {
    pose = Evaluate(*expressions, t);
  } else if (const auto* waypoints = std::get_if<std::vector<Waypoint>>(&form_)) {
    pose = Interpolate(*waypoints, t);
  } else {
    pose = AtConstantTwist(std::get<ConstantTwist>(form_), t);
  }
  // the engine squares coordinates (residual norms): the format's range for any number
  if (!(pose.p.cwiseAbs().maxCoeff() <= kMaxMagnitude)) {
    throw InputError(
        fmt::format("{}: the position at t = {} s is {} m: expected coordinates "
                    "within ±{:g} m",
                    where_, t, ShowNumbers(pose.p.data(), 3), kMaxMagnitude));
  }
  return pose;
}

KinematicMotion::Twist KinematicMotion::StepTwist(double t, double h) const {
  ECPSIM_DEMAND(std::isfinite(t) && std::isfinite(h) && h > 0);
  const auto refuse = [&](const std::string& how) {
    throw InputError(fmt::format(
        "{}: the step from t = {} s to {} s (h = {} s) turns the body by {}: expected a turn "
        "below π per step (a half turn or more in one step has no direction the step can "
        "represent); use a smaller h or a slower turn",
        where_, t, t + h, h, how));
  };

  // a constant twist is its own step twist
  if (const auto* constant = std::get_if<ConstantTwist>(&form_)) {
    const double turn = constant->w.norm() * h;
    if (turn >= kMaxKinematicTurn) refuse(fmt::format("|ω| h = {:.9g} rad", turn));
    return {constant->v, constant->w};
  }

  // the chord between the step's ends, which the engine's update c + h v, Exp(h ω) R reaches
  const KinematicPose begin = PoseAt(t);
  const KinematicPose end = PoseAt(t + h);
  const Eigen::Vector3d phi = QuaternionLog(end.q * begin.q.conjugate());
  const double turn = phi.norm();
  if (turn >= kMaxKinematicTurn) refuse(fmt::format("{:.9g} rad between its ends", turn));

  // a turn wrapped past π: the chord's midpoint is far from the motion's
  const KinematicPose middle = PoseAt(t + 0.5 * h);
  const double deviation = Turn(QuaternionExp(0.5 * phi) * begin.q, middle.q);
  if (deviation > kMaxMidpointDeviation) {
    refuse(
        fmt::format("{:.6g} rad between its ends, but its orientation at mid-step is {:.6g} "
                    "rad away from that turn's (more than π/2: it turned past π, the other "
                    "way round)",
                    turn, deviation));
  }
  return {(end.p - begin.p) / h, phi / h};
}

}  // namespace ecpsim::engine
