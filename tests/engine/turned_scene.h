#pragma once
// A scene turned about the world's vertical axis z through the origin, for the engine's
// rotation-invariance harness: gravity is along z, so the turned scene's motion should be the
// original's, turned (tests/engine/turned_scene_test.cpp, ecpsim_rotation_check).

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "engine/kinematic_motion.h"
#include "engine/loads.h"
#include "engine/scene.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine::testing {

/// A turn about world z by an angle (rad). A whole number of quarter turns (angle = k · (π/2) as
/// doubles) permutes and negates coordinates without rounding, so the turn by 0 is the identity
/// bit for bit and four turns by π/2 give back every vector bit for bit; any other angle rounds
/// once per product, as R v does.
class TurnAboutZ {
 public:
  explicit TurnAboutZ(double angle) : angle_(angle) {
    ECPSIM_DEMAND(std::isfinite(angle));
    const double quarters = angle / (M_PI / 2);
    if (quarters == std::round(quarters) && std::abs(quarters) < 1e9) {
      quarters_ = static_cast<int>(((static_cast<long long>(quarters) % 4) + 4) % 4);
      // the exact cosines and sines of k π/2
      static constexpr double kCos[] = {1, 0, -1, 0};
      static constexpr double kSin[] = {0, 1, 0, -1};
      c_ = kCos[quarters_];
      s_ = kSin[quarters_];
    } else {
      c_ = std::cos(angle);
      s_ = std::sin(angle);
    }
  }

  double angle() const { return angle_; }
  bool IsIdentity() const { return quarters_ == 0; }
  /// The turn by −angle: exact quarter turns stay exact; otherwise cos and sin keep their bits
  /// and sin changes sign, so R⁻¹ is Rᵀ of the same rounded entries.
  TurnAboutZ Inverse() const { return TurnAboutZ(-angle_); }

  /// R v: x' = c x − s y, y' = s x + c y, z' = z.
  Eigen::Vector3d operator()(const Eigen::Vector3d& v) const {
    return Eigen::Vector3d(Combine(c_, v.x(), -s_, v.y()), Combine(s_, v.x(), c_, v.y()), v.z());
  }

  /// The orientation R q (body → world, then turned), the Hamilton product (cos θ/2, sin θ/2 ẑ) q;
  /// a half turn (w, x, y, z) → (−z, −y, x, w) is exact, other turns round.
  Eigen::Quaterniond operator()(const Eigen::Quaterniond& q) const {
    if (quarters_ == 0) return q;
    if (quarters_ == 2) return Eigen::Quaterniond(-q.z(), -q.y(), q.x(), q.w());
    // a quarter turn's half angle takes the one rounded √½ for both (cos π/4 and sin π/4 round
    // to neighbouring doubles), as ±π/2: a turn by 3π/2 is the turn by −π/2
    const double c = quarters_ < 0 ? std::cos(angle_ / 2) : std::sqrt(0.5);
    const double s = quarters_ < 0 ? std::sin(angle_ / 2) : s_ * std::sqrt(0.5);
    return Eigen::Quaterniond(c * q.w() - s * q.z(), c * q.x() - s * q.y(), c * q.y() + s * q.x(),
                              c * q.z() + s * q.w());
  }

  /// The turned x and y components of a vector whose components are functions of time: each a
  /// combination of the original's x(t) and y(t), written as one expression (a constant where
  /// both are constants, computed as operator() computes it).
  TimeFunction X(const TimeFunction& x, const TimeFunction& y) const {
    return Combination(c_, x, -s_, y);
  }
  TimeFunction Y(const TimeFunction& x, const TimeFunction& y) const {
    return Combination(s_, x, c_, y);
  }

  /// An angle about z (as a yaw, or an axis-angle about ±z) plus this turn: `f` + `turn`, where
  /// `turn` is this turn in the function's unit (rad, or degrees for `rpy`).
  static TimeFunction Plus(const TimeFunction& f, double turn) {
    double value = 0;
    if (IsConstant(f, &value)) return TimeFunction(value + turn);
    return TimeFunction(fmt::format("({})+({:.17g})", f.expression(), turn), "turned angle");
  }

  /// The turn in degrees: exact for quarter turns (k · 90).
  double Degrees() const {
    return quarters_ >= 0 ? 90.0 * std::round(angle_ / (M_PI / 2)) : angle_ * (180 / M_PI);
  }

 private:
  // a x + b y, with the zero term left out (exact for quarter turns: ±x or ±y, signed zeros kept)
  static double Combine(double a, double x, double b, double y) {
    if (b == 0) return a == 1 ? x : a * x;
    if (a == 0) return b == 1 ? y : b * y;
    return a * x + b * y;
  }

  // whether `f` is a plain number (TimeFunction(double) prints the shortest round-trip form)
  static bool IsConstant(const TimeFunction& f, double* value) {
    const std::string& e = f.expression();
    char* end = nullptr;
    *value = std::strtod(e.c_str(), &end);
    return !e.empty() && end == e.c_str() + e.size() && std::isfinite(*value);
  }

  // the term a · f of an expression: (f), -(f) or a*(f); empty for a = 0
  static std::string Term(double a, const TimeFunction& f) {
    if (a == 0) return "";
    if (a == 1) return fmt::format("({})", f.expression());
    if (a == -1) return fmt::format("-({})", f.expression());
    return fmt::format("({:.17g})*({})", a, f.expression());
  }

  static TimeFunction Combination(double a, const TimeFunction& x, double b,
                                  const TimeFunction& y) {
    double cx = 0, cy = 0;
    if (IsConstant(x, &cx) && IsConstant(y, &cy)) return TimeFunction(Combine(a, cx, b, cy));
    const std::string tx = Term(a, x), ty = Term(b, y);
    const std::string sum = tx.empty() ? ty : ty.empty() ? tx : tx + "+" + ty;
    return TimeFunction(sum, "turned load");
  }

  double angle_;
  int quarters_ = -1;  // 0 … 3 for a whole number of quarter turns, else −1
  double c_ = 1, s_ = 0;
};

/// The pose R (p, q).
inline KinematicPose Turned(const TurnAboutZ& R, const KinematicPose& pose) {
  return {R(pose.p), R(pose.q)};
}

/// The motion whose pose at every t is R (the original's pose at t). Expressions: the position's
/// x and y combined, the yaw (rpy) or the angle about ±z (axis-angle) plus the turn; an
/// axis-angle about any other axis cannot be turned in its form (R Exp(a n) is no Exp(a' n')
/// for every t) and fails with ECPSIM_DEMAND.
inline std::shared_ptr<const KinematicMotion> Turned(
    const TurnAboutZ& R, const std::shared_ptr<const KinematicMotion>& motion) {
  if (motion == nullptr || R.IsIdentity()) return motion;
  const KinematicMotion::Form& form = motion->form();
  if (const auto* e = std::get_if<PoseExpressions>(&form)) {
    PoseExpressions turned = *e;
    turned.position[0] = R.X(e->position[0], e->position[1]);
    turned.position[1] = R.Y(e->position[0], e->position[1]);
    if (e->orientation == PoseExpressions::Orientation::kRpy) {
      // Rz(θ) Rz(yaw) Ry(pitch) Rx(roll) = Rz(yaw + θ) Ry(pitch) Rx(roll)
      turned.rpy_deg[2] = TurnAboutZ::Plus(e->rpy_deg[2], R.Degrees());
    } else {
      // Rz(θ) Exp(a ẑ) = Exp((a + θ) ẑ), and Exp(a (−ẑ)) turned is Exp((a − θ) (−ẑ))
      ECPSIM_DEMAND(e->axis.x() == 0 && e->axis.y() == 0);
      turned.angle = TurnAboutZ::Plus(e->angle, e->axis.z() > 0 ? R.angle() : -R.angle());
    }
    return std::make_shared<KinematicMotion>(std::move(turned), motion->where());
  }
  if (const auto* waypoints = std::get_if<std::vector<Waypoint>>(&form)) {
    std::vector<Waypoint> turned = *waypoints;
    for (Waypoint& w : turned) w.pose = Turned(R, w.pose);
    return std::make_shared<KinematicMotion>(std::move(turned), motion->where());
  }
  ConstantTwist twist = std::get<ConstantTwist>(form);
  twist.start = Turned(R, twist.start);
  twist.v = R(twist.v);
  twist.w = R(twist.w);
  return std::make_shared<KinematicMotion>(std::move(twist), motion->where());
}

/// A polyhedral obstacle (a half-space or a fixture) turned: normals and vertices; the offsets
/// d of n · x ≤ d stay (R n · R x = n · x), and so do the vertices' order and the faces, so
/// ties between vertices resolve to the same index. Smooth obstacles fail with ECPSIM_DEMAND
/// (the loader makes none).
inline std::shared_ptr<const geometry::ConvexShape> Turned(
    const TurnAboutZ& R, const std::shared_ptr<const geometry::ConvexShape>& shape) {
  if (R.IsIdentity()) return shape;
  const auto* polyhedron = shape->AsPolyhedron();
  ECPSIM_DEMAND(polyhedron != nullptr);
  geometry::ConvexHull hull = polyhedron->hull();
  for (Eigen::Vector3d& v : hull.vertices) v = R(v);
  for (Eigen::Vector3d& n : hull.normals) n = R(n);
  return std::make_shared<geometry::PolyhedralShape>(std::move(hull));
}

/// `scene` turned about world z through the origin by `angle` rad: every world-frame quantity
/// the Scene holds — gravity, bodies' initial poses and velocities, obstacles, loads, impulses,
/// kinematic bodies' and grippers' motions. Body-frame quantities (meshes, hulls, parts, inertia,
/// load and impulse points, a gripper's axis and its jaws' poses in its frame) stay.
inline Scene TurnedAboutZ(const Scene& scene, double angle) {
  const TurnAboutZ R(angle);
  Scene s = scene;
  if (R.IsIdentity()) return s;
  s.gravity = R(s.gravity);
  for (Body& body : s.bodies) {
    body.p0 = R(body.p0);
    body.q0 = R(body.q0);
    body.v0 = R(body.v0);
    body.w0 = R(body.w0);
    body.motion = Turned(R, body.motion);
  }
  for (Obstacle& obstacle : s.obstacles) obstacle.shape = Turned(R, obstacle.shape);
  for (Load& load : s.loads) {
    // force and torque alike: world-frame vectors
    const TimeFunction x = load.x, y = load.y;
    load.x = R.X(x, y);
    load.y = R.Y(x, y);
  }
  for (Impulse& impulse : s.impulses) {
    impulse.linear = R(impulse.linear);
    impulse.angular = R(impulse.angular);
  }
  for (Gripper& gripper : s.grippers) gripper.motion = Turned(R, gripper.motion);
  return s;
}

}  // namespace ecpsim::engine::testing
