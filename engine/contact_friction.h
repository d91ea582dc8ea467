#pragma once
// The friction a contact's step uses: the pair's (Scene::contacts), with e_r computed from the
// contact patch at the start of the step where the pair asks for it (`e_r: patch`). The one
// place every model's e_r comes from: FormIslands stores it in Island::friction.

#include <Eigen/Core>

#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/contact_patch.h"

namespace ecpsim::engine {

/// The floor on a patch's e_r, relative to the bounding-box diagonal of F's mesh: a patch that is
/// a point has mean distance 0, which the friction rows (e_r² μ p_n ω_n + p_r σ = 0 and the cone's
/// p_r / e_r) cannot take. At 1e-3 of the body's size the torsion the floor allows,
/// μ p_n × 1e-3 L, is negligible beside the moments the body's extent gives its forces, while
/// e_r² stays 1e-6 L², far inside the range the rows' scaling (P e_r for p_r) keeps conditioned;
/// relative, so a millimetre part and a 10 m hull get the same floor in their own scale.
inline constexpr double kPatchTorsionFloorRel = 1e-3;  // dimensionless

/// The mesh of one side of a contact with body `body`: its mesh where the contact touches its hull
/// (part < 0; its hull's tessellation, into `made`, where code built it without one), else part
/// `part`'s tessellation (into `made`).
const geometry::TriangleMesh& ContactMesh(const Body& body, int part, geometry::TriangleMesh& made);

/// Contact k's patch at the start of the step from `state`, and the point its e_r is taken about.
struct StepPatch {
  geometry::Plane plane;         // the patch's plane: n out of G, through F's nearest mesh vertex
  geometry::ContactPatch patch;  // world, on `plane`
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the last step's ECP a1, or the centroid
  bool at_ecp = false;  // true: `centre` is the last step's ECP (it had p_n > 0)
};

/// The patch of scene.contacts[k] at the poses of `state`: the features of F's mesh within the
/// patch tolerance (geometry::ContactPatchTolerance) of F's nearest vertex (of the part's mesh
/// where the contact names one) along the contact
/// normal n — G's plane's for a half-space obstacle, else the last step's contact normal where it
/// had p_n > 0, else the hulls' best separating axis (geometry::BestSeparatingAxis) — clipped,
/// where G is a body or a bounded obstacle, to G's features nearest F (its mesh, or the obstacle's
/// tessellation) by geometry::IntersectContactPatches. Touching, that is where they touch; apart,
/// it is where they would touch first moving toward each other along n (so a body landing flat
/// lands with its face's e_r, one landing on a corner with the floor).
/// ECPSIM_DEMAND: 0 ≤ k < scene.contacts.size() and `state` the scene's.
StepPatch ContactPatchAtStep(const Scene& scene, const State& state, int k);

/// e_r (m) for contact k's step from `state`: the mean distance of ContactPatchAtStep's patch from
/// its centre (geometry::PatchMeanDistance: the largest friction moment over the largest friction
/// force under uniform pressure), at least kPatchTorsionFloorRel × F's mesh diagonal.
double PatchTorsionArm(const Scene& scene, const State& state, int k);

/// The friction of contact k for the step that starts at `state`: scene.contacts[k].friction,
/// with e_r = PatchTorsionArm where it has e_r_patch (else unchanged, to the bit).
Friction StepFriction(const Scene& scene, const State& state, int k);

}  // namespace ecpsim::engine
