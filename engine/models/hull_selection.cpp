#include "engine/models/hull_selection.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/contact_friction.h"
#include "engine/mncp/contact_frame.h"
#include "engine/mncp/mncp_layout.h"
#include "engine/models/hull_tuning.h"
#include "geometry/contact_patch.h"
#include "geometry/patch_moments.h"
#include "geometry/support_patch.h"

namespace ecpsim::engine::hull {

using Eigen::Isometry3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

namespace {

constexpr int kEnergyRows = 6;  // per contact
// a line or a point contact as a thin patch: strips and squares of this width relative to the
// body's size. Where on the line or among the points the ECP sits does not depend on it (every
// term of one contact scales with it alike); only the load a line shares with a patch does
constexpr double kFeatureWidthRel = 1e-3;
// a second moment this much below the other is a line's across it: no offset to weigh
constexpr double kNegligibleMomentRel = 1e-12;
// two selections whose energies differ by less than this are one: the first is kept (the
// energies of one least point, each evaluated with the patches at its own root)
constexpr double kEnergyTieRel = 1e-9;

struct PatchFrame {
  geometry::PatchMoments moments;
  ContactFrame frame;
};

Isometry3d AsIsometry(const EndPose& pose) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = pose.R;
  X.translation() = pose.c;
  return X;
}

// a body's features on `plane`: its mesh's where its hull is a polyhedron (a desk's four feet, not
// their hull), its hull's support features where the hull is smooth (a cylinder's side is a
// segment, which no tessellation of it lays on the plane in every frame)
geometry::ContactPatch FeaturesOn(const geometry::ConvexShape& hull,
                                  const geometry::TriangleMesh& mesh, const Isometry3d& X,
                                  const geometry::Plane& plane) {
  if (hull.AsPolyhedron() != nullptr) return geometry::ExtractContactPatch(mesh, X, plane);
  return geometry::SupportPatch(hull, X, plane, geometry::ContactPatchTolerance(mesh));
}

PatchFrame PatchAt(const Scene& scene, const Island& island, const IslandProblem& problem,
                   const IslandLayout& layout, const VectorXd& z, int k) {
  const IslandContact& cp = problem.contacts[k];
  const MncpLayout::Contact& L = layout.contacts[k];
  const ContactPair& pair = scene.contacts[island.contacts[k]];
  PatchFrame out;
  const Vector3d n = IslandContactNormal(problem, layout, z, k).normalized();
  out.frame = MakeContactFrame(n, cp.tangent_reference);
  const Vector3d a2 =
      L.on_plane() ? ContactGapAt(L, cp.other_shape, z).a2 : Vector3d(z.segment<3>(L.a2));
  const int col = IslandLayout::Velocity(cp.body);
  const EndPose end =
      PoseAfterStep(problem.bodies[cp.body], z.segment<3>(col), z.segment<3>(col + 3));
  const geometry::Plane plane{n, n.dot(a2)};
  geometry::TriangleMesh made, made_other;
  const geometry::TriangleMesh& mesh = ContactMesh(scene.bodies[pair.body], pair.part, made);
  geometry::ContactPatch patch = FeaturesOn(*cp.hull, mesh, AsIsometry(end), plane);
  if (cp.other_kind != Other::kFixed) {
    const geometry::Plane flipped{-n, -n.dot(a2)};
    const geometry::ContactPatch other_patch = FeaturesOn(
        *cp.other_shape, ContactMesh(scene.bodies[pair.other_body], pair.other_part, made_other),
        AsIsometry(OtherEndPose(problem, z, k)), flipped);
    patch = geometry::IntersectContactPatches(patch, other_patch, plane,
                                              geometry::ContactPatchTolerance(mesh));
  }
  const double diagonal =
      geometry::ContactPatchTolerance(mesh) / geometry::kContactPatchRelTolerance;
  out.moments = geometry::MomentsOf(patch, plane, kFeatureWidthRel * diagonal);
  return out;
}

}  // namespace

EnergyResiduals PatchEnergy(const Scene& scene, const Island& island, const IslandProblem& problem,
                            const IslandLayout& layout, const VectorXd& z) {
  std::vector<PatchFrame> patches;
  for (size_t k = 0; k < problem.contacts.size(); ++k)
    patches.push_back(PatchAt(scene, island, problem, layout, z, static_cast<int>(k)));
  return [patches, contacts = layout.contacts](const VectorXd& zz, VectorXd* r, MatrixXd* R) {
    const int m = kEnergyRows * static_cast<int>(contacts.size());
    r->setZero(m);
    if (R != nullptr) R->setZero(m, zz.size());
    for (size_t k = 0; k < contacts.size(); ++k) {
      const MncpLayout::Contact& L = contacts[k];
      const geometry::PatchMoments& pm = patches[k].moments;
      if (!(pm.area > 0)) continue;  // no patch: nothing touches
      const ContactFrame& f = patches[k].frame;
      const double a = 1 / std::sqrt(pm.area);
      const double i1 = pm.I1 > 0 ? 1 / std::sqrt(pm.I1) : 0;
      const double i2 = pm.I2 > kNegligibleMomentRel * pm.I1 ? 1 / std::sqrt(pm.I2) : 0;
      const double j = 1 / std::sqrt(pm.I1 + pm.I2);
      const Vector3d d = zz.segment<3>(L.a1) - pm.centroid;
      const double p_n = zz[L.p_n], p_t = zz[L.p_t], p_o = zz[L.p_o], p_r = zz[L.p_r];
      const double e1 = pm.u1.dot(d), e2 = pm.u2.dot(d);
      const double moment = -p_t * d.dot(f.o) + p_o * d.dot(f.t);
      const int row = kEnergyRows * static_cast<int>(k);
      (*r)[row] = p_n * a;
      (*r)[row + 1] = p_n * e1 * i1;
      (*r)[row + 2] = p_n * e2 * i2;
      (*r)[row + 3] = p_t * a;
      (*r)[row + 4] = p_o * a;
      (*r)[row + 5] = (p_r + moment) * j;
      if (R == nullptr) continue;
      (*R)(row, L.p_n) = a;
      (*R)(row + 1, L.p_n) = e1 * i1;
      R->block<1, 3>(row + 1, L.a1) = p_n * i1 * pm.u1.transpose();
      (*R)(row + 2, L.p_n) = e2 * i2;
      R->block<1, 3>(row + 2, L.a1) = p_n * i2 * pm.u2.transpose();
      (*R)(row + 3, L.p_t) = a;
      (*R)(row + 4, L.p_o) = a;
      (*R)(row + 5, L.p_r) = j;
      (*R)(row + 5, L.p_t) = -d.dot(f.o) * j;
      (*R)(row + 5, L.p_o) = d.dot(f.t) * j;
      R->block<1, 3>(row + 5, L.a1) = j * (p_o * f.t - p_t * f.o).transpose();
    }
  };
}

RootSelection SelectLeastEnergyRoot(const Scene& scene, const Island& island,
                                    const IslandProblem& problem, const IslandLayout& layout,
                                    const IslandScales& scales, double ejection_energy,
                                    double tolerance, StepWorkspace& workspace, VectorXd& z,
                                    const VectorXd* last) {
  RootSelection selection;
  IslandProblem exact = problem;
  for (IslandContact& cp : exact.contacts) cp.stick_creep = 0;
  VectorXd row_scale, var_scale;
  IslandResidualUnits units;
  IslandRowScales(exact, layout, scales, row_scale);
  IslandVariableScales(exact, layout, scales, var_scale);
  MakeIslandResidualUnits(exact, scales, tolerance, units);
  McpOptions options;
  options.tolerance = tolerance;
  options.minimum_norm_steps = true;
  options.max_iterations = scene.solver.max_iterations;
  options.stall_iterations = kNearSetStallIterations;
  options.measure = [&](const VectorXd& zz, const VectorXd& F) {
    return IslandMncpResidual(exact, layout, zz, F, row_scale, var_scale, units);
  };
  const McpFunction f = [&](const VectorXd& zz, VectorXd* F, MatrixXd* J) {
    EvaluateIslandMncp(exact, layout, zz, F, J, /*jacobian_is_zero=*/true);
  };
  // a contact's friction impulses and σ move along the set only while it bears a load
  std::vector<int> ties(layout.size, -1);
  for (const MncpLayout::Contact& L : layout.contacts)
    for (int i : {L.p_t, L.p_o, L.p_r, L.sigma}) ties[i] = L.p_n;
  McpWorkspace& solver_workspace = workspace.Part<McpWorkspace>();
  const double allowed_gain =
      kMaxEnergyGainRel * IslandEnergyScale(exact, scales) + ejection_energy;
  // `root` taken to the exact root nearest it and along that root's set to the least energy;
  // its E, or NaN
  const auto select_from = [&](VectorXd& root, SelectionResult& result) -> double {
    if (!SolveMcp(f, layout.num_free, row_scale, var_scale, root, options, solver_workspace)
             .converged)
      return NAN;
    result = SelectLeastEnergySolution(f, layout.num_free, row_scale, var_scale,
                                       PatchEnergy(scene, island, exact, layout, root), root,
                                       options, solver_workspace, ties);
    if (!result.converged || IslandStepEnergyGain(exact, layout, root) > allowed_gain) return NAN;
    return result.energy;
  };
  const auto loaded = [&](const VectorXd& zz, const MncpLayout::Contact& L) {
    return zz[L.p_n] > tolerance * var_scale[L.p_n];
  };
  // whether every loaded contact of a selected root sticks with its friction inside its limit
  // (σ = 0 and its pair not degenerate)
  const auto sticks = [&](const VectorXd& zz, const SelectionResult& r) {
    return std::none_of(layout.contacts.begin(), layout.contacts.end(), [&](const auto& L) {
      return loaded(zz, L) &&
             (zz[L.sigma] > tolerance * var_scale[L.sigma] ||
              std::find(r.degenerate.begin(), r.degenerate.end(), L.sigma) != r.degenerate.end());
    });
  };
  VectorXd root = z;
  SelectionResult result;
  double energy = select_from(root, result);
  // the set may come in pieces that no path along it joins (a held grasp's, and a slipping one's
  // where its pads' ECPs left the centre): the piece the last step's solution continues is
  // searched too. A piece that sticks everywhere inside the friction limits is taken over one
  // that slips (compliance holds what friction can hold at its least point); else the lesser
  // energy. A last solution that is z itself (a selected start that holds) would repeat the
  // selection from z bit for bit
  if (last != nullptr && !(last->size() == z.size() && *last == z)) {
    VectorXd other = *last;
    SelectionResult other_result;
    const double other_energy = select_from(other, other_result);
    const bool root_sticks = !std::isnan(energy) && sticks(root, result);
    const bool other_sticks = !std::isnan(other_energy) && sticks(other, other_result);
    const bool take_other =
        !std::isnan(other_energy) &&
        (std::isnan(energy) || (other_sticks && !root_sticks) ||
         (other_sticks == root_sticks && other_energy < energy * (1 - kEnergyTieRel)));
    if (take_other) {
      root.swap(other);
      result = other_result;
      energy = other_energy;
    }
  }
  if (std::isnan(energy)) return selection;
  selection.selected = true;
  selection.directions = result.directions;
  selection.steps = result.steps;
  z = root;
  return selection;
}

}  // namespace ecpsim::engine::hull
