#include "engine/auto_model.h"

#include <cmath>

#include "engine/planar_model.h"
#include "engine/state.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

// Whether a planar step can be the hull model's step (engine/README.md, "model: auto", the
// conditions before the solve): one body, one contact with a fixed plane, the body moving in the
// plane and turning about its normal only, to the solver's tolerance in the body's own scales,
// and the normal a principal axis of its inertia (otherwise spinning about it tips the body).
bool PlanarMotion(const Scene& scene, const Island& island, const IslandState& state) {
  if (island.bodies.size() != 1 || island.contacts.size() != 1) return false;
  const ContactPair& pair = scene.contacts[island.contacts[0]];
  if (pair.WithBody()) return false;
  const geometry::ConvexShape& plane = *scene.obstacles[pair.obstacle].shape;
  const Body& body = scene.bodies[island.bodies[0]];
  if (!plane.IsHalfSpace() || body.hull->AsPolyhedron() == nullptr) return false;
  const BodyState& b = state.bodies[0];
  const Vector3d N = plane.Gradient(0, b.p_WB).normalized();
  const double tolerance = scene.solver.tolerance;
  const double length = std::sqrt(body.inertia.trace() / body.mass);
  // the body's velocity scale, at most BodyScales' (so the test is at least as strict)
  const double speed = std::max(b.v_WB.norm() + b.w_WB.norm() * length, scene.gravity.norm() * scene.h);
  if (std::abs(N.dot(b.v_WB)) > tolerance * speed) return false;
  if (b.w_WB.cross(N).norm() * length > tolerance * speed) return false;
  const Eigen::Matrix3d R = b.Q_WB.toRotationMatrix();
  const Vector3d IN = R * (body.inertia * (R.transpose() * N));
  return IN.cross(N).norm() <= tolerance * N.dot(IN);
}

}  // namespace

AdvanceResult AutoModel::Advance(const Island& island, double t, double h,
                                 IslandState& state) const {
  int planar_iterations = 0;
  if (PlanarMotion(scene_, island, state)) {
    // the support face flat on the plane, the lowest point on it and the ECP on the face, all to
    // the tolerance in the body's length (the conditions after the solve)
    const double tolerance = scene_.solver.tolerance;
    // a turn beyond π in a step is an alias the hull model refuses (hull_model.cpp): not taken
    const PlanarStep step =
        SolvePlanarStep(scene_, island, t, h, {tolerance, tolerance, M_PI}, state);
    if (step.invalid.empty() && step.result.solved) {
      // the hull model's unknowns at this solution, for when it takes over: a1 = a2 (s = 0), the
      // support face's multiplier 1 (its normal is −N), the plane's 1
      state.contacts[0].warm_start = HullWarmStart{0.0, Eigen::VectorXd::Ones(1), {step.face},
                                                   Eigen::VectorXd::Ones(1), {}};
      return step.result;
    }
    planar_iterations = step.result.iterations;
  }
  AdvanceResult result = hull_.Advance(island, t, h, state);
  result.iterations += planar_iterations;
  return result;
}

}  // namespace ecpsim::engine
