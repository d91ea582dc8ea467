#pragma once
// The prescribed motion of a kinematic body (one that pushes and is never pushed): its pose as
// expressions of t, by waypoints, or at a constant twist, and the twist of each time step that
// takes it from the pose at the step's start to the pose at its end in the engine's update.

#include <array>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/loads.h"

namespace ecpsim::engine {

/// rad: the largest turn of a kinematic body in one step, and between two consecutive
/// waypoints. A turn of π reaches its end orientation the other way round just as well, so the
/// direction is undefined there; within 1e-9 rad of π it is decided by the quaternions'
/// round-off (the direction is the sign of cos(θ/2) ≈ (π − θ)/2, known to ~1e-16).
inline constexpr double kMaxKinematicTurn = M_PI - 1e-9;

/// An axis-angle axis shorter than this has no direction (as a plane normal's).
inline constexpr double kMinRotationAxisLength = 1e-12;

/// The pose of a kinematic body at one time.
struct KinematicPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            // m, world: the body frame's origin (CM)
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // unit, body → world
};

/// Position and orientation as functions of t (s), each a TimeFunction (a number or a muparser
/// expression of t).
struct PoseExpressions {
  std::array<TimeFunction, 3> position;  // m, world: x(t), y(t), z(t)
  enum class Orientation { kRpy, kAxisAngle };
  Orientation orientation = Orientation::kRpy;
  // kRpy: [roll, pitch, yaw](t) in degrees, like the format's every `rpy`: R = Rz(yaw) ·
  // Ry(pitch) · Rx(roll), i.e. about the fixed world x axis, then world y, then world z
  std::array<TimeFunction, 3> rpy_deg;
  // kAxisAngle: R = Exp(angle(t) · axis), a turn about one fixed world axis
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // world; normalized by KinematicMotion
  TimeFunction angle;                               // rad
};

/// A prescribed pose at time t.
struct Waypoint {
  double t = 0;  // s
  KinematicPose pose;
};

/// A constant twist from a pose at t = 0: pose(t) = (p0 + v t, Exp(ω t) R0).
struct ConstantTwist {
  KinematicPose start;                          // the pose at t = 0
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // m/s, world
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  // rad/s, world
};

/// A kinematic body's prescribed motion, in one of three forms:
/// - expressions: pose(t) as given;
/// - waypoints: the first pose before the first waypoint, the last after the last, and between
///   two waypoints the position linearly and the orientation by slerp (the shortest arc), i.e.
///   a constant twist per segment. Linear, not C¹ (a cubic spline): the path stays on the
///   segments between the waypoints, so a finger whose waypoints clear the table clears it all
///   the way (a spline through them can overshoot into it), and each segment is exactly one
///   constant twist, what one engine step applies; the velocity jumps at a waypoint, as a
///   position-controlled robot's does; a smooth start is a few more waypoints or an expression;
/// - a constant twist.
/// Thread-safe: copies share compiled expressions, whose evaluation is serialized (TimeFunction).
class KinematicMotion {
 public:
  /// The body's twist over a step: linear velocity of its origin and angular velocity.
  struct Twist {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();  // m/s, world
    Eigen::Vector3d w = Eigen::Vector3d::Zero();  // rad/s, world
  };

  /// `where` ("scenes/push.yaml:12:7: bodies[1].motion") starts the messages of later errors.
  /// @throws InputError if the axis (kAxisAngle) is not finite or is zero.
  KinematicMotion(PoseExpressions expressions, std::string where);
  /// @throws InputError if there is no waypoint, a number is not finite or beyond ±1e150, a
  ///         quaternion is zero (the others are normalized), the times do not strictly
  ///         increase, or two consecutive orientations are kMaxKinematicTurn or more apart
  ///         (the shortest arc between them is ambiguous).
  KinematicMotion(std::vector<Waypoint> waypoints, std::string where);
  /// @throws InputError if a number is not finite or beyond ±1e150, or the quaternion is zero.
  KinematicMotion(ConstantTwist twist, std::string where);

  /// The prescribed pose at t (s); q is unit.
  /// @throws InputError naming `where` and t if an expression is not finite at t, or a position
  ///         coordinate lies beyond ±1e150 m.
  KinematicPose PoseAt(double t) const;

  /// The twist (v, ω) that takes the pose at t to the pose at t + h in the engine's update
  /// c⁺ = c + h v, R⁺ = Exp(h ω) R: v = (p(t + h) − p(t)) / h, ω = Log(R(t + h) R(t)ᵀ) / h,
  /// exact up to round-off; for a constant twist, (v, ω) themselves. The engine takes the pose
  /// at the end of step k from PoseAt((k + 1) h) (never a running sum of c + h v, which drifts
  /// by round-off), so a constant velocity with ω = 0 gives p0 + v (k h) at every step; with
  /// t = k h, t + h is (k + 1) h up to one rounding.
  /// Precondition: t and h finite, h > 0.
  /// @throws InputError naming `where`, t and h if the body turns by kMaxKinematicTurn or more
  ///         in the step — its direction then is ambiguous —, detected from the two ends (for
  ///         a constant twist, |ω| h) and the midpoint: a turn past π wraps the chord the other
  ///         way round, π away from the true midpoint; or as PoseAt.
  Twist StepTwist(double t, double h) const;

  const std::string& where() const { return where_; }

  /// The motion in the form it was given (waypoint and twist quaternions normalized, the
  /// axis-angle axis normalized): for code that derives another motion from it, e.g. the
  /// tests' scene turned about z (tests/engine/turned_scene.h).
  using Form = std::variant<PoseExpressions, std::vector<Waypoint>, ConstantTwist>;
  const Form& form() const { return form_; }

 private:
  Form form_;
  std::string where_;
};

}  // namespace ecpsim::engine
