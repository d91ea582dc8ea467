#include "engine/contact_friction.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/errors.h"
#include "geometry/convex_separation.h"
#include "geometry/patch_moments.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

// the extreme of `mesh` posed by X along `direction`: max over its vertices of direction · x
double Extreme(const geometry::TriangleMesh& mesh, const Eigen::Isometry3d& X,
               const Vector3d& direction) {
  double extreme = -std::numeric_limits<double>::infinity();
  for (const Vector3d& v : mesh.vertices) extreme = std::max(extreme, direction.dot(X * v));
  return extreme;
}

// the half-space G = {x : n · x ≤ offset} of a linear obstacle constraint f(y) = g · y − d
geometry::Plane HalfSpacePlane(const geometry::ConvexShape& shape) {
  const Vector3d gradient = shape.Gradient(0, Vector3d::Zero());
  const double scale = gradient.norm();
  return {gradient / scale, -shape.Value(0, Vector3d::Zero()) / scale};
}

}  // namespace

const geometry::TriangleMesh& ContactMesh(const Body& body, int part,
                                          geometry::TriangleMesh& made) {
  if (part >= 0) {
    made = body.parts.at(part)->Tessellate();
    return made;
  }
  if (!body.mesh.vertices.empty()) return body.mesh;
  ECPSIM_DEMAND(body.hull != nullptr);
  made = body.hull->Tessellate();
  return made;
}

StepPatch ContactPatchAtStep(const Scene& scene, const State& state, int k) {
  ECPSIM_DEMAND(k >= 0 && k < static_cast<int>(scene.contacts.size()));
  ECPSIM_DEMAND(state.contacts.size() == scene.contacts.size() &&
                state.bodies.size() == scene.bodies.size());
  const ContactPair& pair = scene.contacts[k];
  const ContactState& c = state.contacts[k];
  const geometry::ConvexShape* obstacle =
      pair.WithBody() ? nullptr : scene.obstacles[pair.obstacle].shape.get();
  // the normal: a plane's own; else the last step's where it touched, and where it did not (or
  // before any step) the axis that separates the hulls best (out of G, the last normal a hint)
  Vector3d n = c.n;
  if (obstacle != nullptr && obstacle->IsHalfSpace()) {
    n = HalfSpacePlane(*obstacle).normal;
  } else if (!(c.p_n > 0)) {
    const Eigen::Isometry3d X_G =
        obstacle ? Eigen::Isometry3d::Identity() : PoseOf(state.bodies[pair.other_body]);
    n = geometry::BestSeparatingAxis(ShapeOfBody(scene, pair), PoseOf(state.bodies[pair.body]),
                                     ShapeOfOther(scene, pair), X_G, {c.n})
            .axis;
  }
  if (!(n.allFinite() && n.norm() > 0)) n = Vector3d::UnitZ();
  n.normalize();

  // F's features nearest G: its mesh's lowest level along n
  geometry::TriangleMesh made_F, made_G;
  const geometry::TriangleMesh& mesh_F = ContactMesh(scene.bodies[pair.body], pair.part, made_F);
  const Eigen::Isometry3d X_F = PoseOf(state.bodies[pair.body]);
  StepPatch step;
  step.plane = {n, -Extreme(mesh_F, X_F, -n)};
  double tolerance = geometry::ContactPatchTolerance(mesh_F);
  step.patch = geometry::ExtractContactPatch(mesh_F, X_F, step.plane, tolerance);

  // G's features nearest F, where G is bounded: a body's mesh, an obstacle's tessellation
  if (obstacle == nullptr || !obstacle->IsHalfSpace()) {
    if (obstacle != nullptr) made_G = obstacle->Tessellate();
    const geometry::TriangleMesh& mesh_G =
        obstacle ? made_G : ContactMesh(scene.bodies[pair.other_body], pair.other_part, made_G);
    const Eigen::Isometry3d X_G =
        obstacle ? Eigen::Isometry3d::Identity() : PoseOf(state.bodies[pair.other_body]);
    const geometry::Plane below{-n, -Extreme(mesh_G, X_G, n)};
    const double tolerance_G = geometry::ContactPatchTolerance(mesh_G);
    tolerance = std::max(tolerance, tolerance_G);
    const geometry::ContactPatch patch_G =
        geometry::ExtractContactPatch(mesh_G, X_G, below, tolerance);
    // IntersectContactPatches works in the plane's coordinates: G's features, a gap below F's
    // when apart, clip F's where they overlap seen along n
    step.patch = geometry::IntersectContactPatches(step.patch, patch_G, step.plane, tolerance);
  }

  // about the last step's ECP where it had one (projected on the plane), else the centroid
  step.at_ecp = c.p_n > 0 && c.a1.allFinite();
  step.centre = step.at_ecp ? Vector3d(c.a1 - (n.dot(c.a1) - step.plane.offset) * n)
                            : geometry::PatchCentroid(step.patch, step.plane);
  return step;
}

double PatchTorsionArm(const Scene& scene, const State& state, int k) {
  const StepPatch step = ContactPatchAtStep(scene, state, k);
  geometry::TriangleMesh made;
  const ContactPair& pair = scene.contacts[k];
  const geometry::TriangleMesh& mesh_F = ContactMesh(scene.bodies[pair.body], pair.part, made);
  Vector3d lo = mesh_F.vertices.front(), hi = lo;
  for (const Vector3d& v : mesh_F.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double floor = kPatchTorsionFloorRel * (hi - lo).norm();
  return std::max(geometry::PatchMeanDistance(step.patch, step.plane, step.centre), floor);
}

Friction StepFriction(const Scene& scene, const State& state, int k) {
  Friction friction = scene.contacts[k].friction;
  if (friction.e_r_patch) friction.e_r = PatchTorsionArm(scene, state, k);
  return friction;
}

}  // namespace ecpsim::engine
