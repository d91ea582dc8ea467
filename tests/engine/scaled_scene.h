#pragma once
// A scene and its exactly similar copy L times larger (Froude scaling: the same gravity), for the
// engine's scale-invariance tests.

#include <cmath>
#include <memory>
#include <regex>
#include <string>

#include <fmt/format.h>
#include <Eigen/Core>

#include "common/errors.h"
#include "engine/loads.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine::testing {

/// The units of a scene scaled by L with gravity unchanged: lengths × L, times and velocities
/// × √L, angular velocities × 1/√L, masses × L³, forces × L³, torques × L⁴, impulses × L³√L.
/// A motion of the original is a motion of the scaled scene in these units: the continuous
/// equations, the discrete step (h × √L) and the contact conditions are all invariant.
struct FroudeUnits {
  explicit FroudeUnits(double L) : length(L), time(std::sqrt(L)) {}
  double length;                                     // m per unit
  double time;                                       // s per unit
  double velocity() const { return length / time; }  // m/s per unit
  double mass() const { return length * length * length; }
  double force() const { return mass() * length / (time * time); }
  double torque() const { return force() * length; }
  double impulse() const { return force() * time; }
};

/// A polyhedral shape (a hull or a half-space) with every length × L.
inline std::shared_ptr<const geometry::ConvexShape> ScaledPolyhedron(
    const geometry::ConvexShape& shape, double L) {
  const auto* polyhedron = shape.AsPolyhedron();
  ECPSIM_DEMAND(polyhedron != nullptr);  // the scale tests use polyhedral hulls and planes only
  geometry::ConvexHull hull = polyhedron->hull();
  for (Eigen::Vector3d& v : hull.vertices) v *= L;
  for (double& d : hull.offsets) d *= L;
  return std::make_shared<geometry::PolyhedralShape>(std::move(hull));
}

/// `f` of the scaled scene: the original's value × `factor` at the original's time t / time.
inline TimeFunction ScaledFunction(const TimeFunction& f, double factor, double time) {
  const std::string expression =
      std::regex_replace(f.expression(), std::regex(R"(\bt\b)"), fmt::format("(t/{:.17g})", time));
  return TimeFunction(fmt::format("({})*{:.17g}", expression, factor), "scaled load");
}

/// `scene` L times larger (see FroudeUnits); polyhedral hulls, parts and obstacles only.
inline Scene ScaledScene(const Scene& scene, double L) {
  const FroudeUnits u(L);
  Scene s = scene;
  s.h *= u.time;
  s.duration *= u.time;
  for (Body& body : s.bodies) {
    for (Eigen::Vector3d& v : body.mesh.vertices) v *= L;
    body.hull = ScaledPolyhedron(*body.hull, L);
    for (auto& part : body.parts) part = ScaledPolyhedron(*part, L);
    body.mass *= u.mass();
    body.inertia *= u.mass() * L * L;
    body.p0 *= L;
    body.v0 *= u.velocity();
    body.w0 /= u.time;
  }
  for (Obstacle& obstacle : s.obstacles) {
    obstacle.shape = ScaledPolyhedron(*obstacle.shape, L);
    obstacle.friction.e_r *= L;
  }
  for (ContactPair& pair : s.contacts) pair.friction.e_r *= L;
  for (Load& load : s.loads) {
    const double factor = load.kind == Load::Kind::kForce ? u.force() : u.torque();
    load.x = ScaledFunction(load.x, factor, u.time);
    load.y = ScaledFunction(load.y, factor, u.time);
    load.z = ScaledFunction(load.z, factor, u.time);
    load.point_B *= L;
    load.start *= u.time;
    if (load.end < 1e300) load.end *= u.time;
  }
  for (Impulse& impulse : s.impulses) {
    impulse.time *= u.time;
    impulse.linear *= u.impulse();
    impulse.angular *= u.impulse() * L;
    impulse.point_B *= L;
  }
  return s;
}

/// A body state of the scaled scene in the original's units.
inline BodyState InOriginalUnits(const BodyState& b, double L) {
  const FroudeUnits u(L);
  BodyState out = b;
  out.p_WB /= L;
  out.v_WB /= u.velocity();
  out.w_WB *= u.time;
  return out;
}

}  // namespace ecpsim::engine::testing
