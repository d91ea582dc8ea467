#include "engine/models/hull_stall_recovery.h"

#include <algorithm>
#include <cmath>

#include "engine/mncp/mncp_scaling.h"
#include "engine/mncp/mncp_system.h"
#include "engine/models/hull_problem.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

// SolveAlongCarryingEdge on contact `stalled` alone
bool SolveAlongEdgeOf(int stalled, const IslandProblem& problem, const IslandLayout& layout,
                      const VectorXd& z, McpOptions& options, const IslandScales& scales,
                      double ejection_energy, StepWorkspace& workspace, IslandState& state,
                      AdvanceResult& result, const RootSelector& select) {
  const IslandContact& cp = problem.contacts[stalled];
  const MncpLayout::Contact& L = layout.contacts[stalled];
  const std::vector<int> carrying = Carrying(z, L.l, L.l_count);  // window positions
  if (carrying.size() != 2) return false;
  // the edge's direction in F's end-of-step frame, and the hull's extent along it
  const int col = IslandLayout::Velocity(cp.body);
  const EndPose end =
      PoseAfterStep(problem.bodies[cp.body], z.segment<3>(col), z.segment<3>(col + 3));
  const Vector3d y = end.R.transpose() * (z.segment<3>(L.a1) - end.c);
  const Vector3d edge_body = cp.hull->Gradient(cp.window[carrying[0]], y)
                                 .cross(cp.hull->Gradient(cp.window[carrying[1]], y));
  if (!(edge_body.norm() > 0)) return false;
  const Vector3d e = edge_body.normalized();
  const double from = (cp.hull->Support(-e) - y).dot(e), to = (cp.hull->Support(e) - y).dot(e);
  std::vector<double> shifts;
  for (int i = 0; i < kEdgeStarts; ++i)
    shifts.push_back(from + (to - from) * (i + 0.5) / kEdgeStarts);
  std::sort(shifts.begin(), shifts.end(),
            [](double a, double b) { return std::abs(a) < std::abs(b); });
  // the starts' bases: the stalled iterate and each carrying face's own root
  std::vector<VectorXd> bases = {z};
  for (int face : carrying) {
    IslandProblem single = problem;
    single.contacts[stalled].window = {cp.window[face]};
    const IslandLayout single_layout = MakeIslandLayout(single);
    VectorXd sz = RemapWindows(problem, layout, z, single, single_layout);
    if (SolveAttempt(single, single_layout, sz, options, scales, ejection_energy, workspace, result)
            .outcome == Outcome::kSolved) {
      bases.push_back(RemapWindows(single, single_layout, sz, problem, layout));
    }
  }
  const Vector3d e_world = end.R * e;
  for (double shift : shifts) {
    for (const VectorXd& base : bases) {
      VectorXd start = base;
      start.segment<3>(L.a1) += shift * e_world;
      if (!L.on_plane()) start.segment<3>(L.a2) += shift * e_world;
      const Attempt attempt =
          SolveAttempt(problem, layout, start, options, scales, ejection_energy, workspace, result);
      if (AcceptReduced(problem, layout, start, attempt, scales, state, result, select))
        return true;
    }
  }
  return false;
}

}  // namespace

bool IsNearSolutionStall(const IslandLayout& layout, const Attempt& attempt, double tolerance) {
  const double factor = layout.num_bodies == 1 ? kMaxOneBodyStall : kMaxDegenerateStall;
  return attempt.residual <= factor * tolerance;
}

bool ReSolveStall(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                  McpOptions& options, const IslandScales& scales, double ejection_energy,
                  StepWorkspace& workspace, IslandState& state, AdvanceResult& result,
                  const RootSelector& select) {
  return SolveOnCarryingFaces(problem, layout, z, options, scales, ejection_energy, workspace,
                              state, result, select) ||
         SolveAtDegenerateVertex(problem, layout, z, options, scales, ejection_energy, workspace,
                                 state, result, kMaxDegenerateDrops, select) ||
         SolveAlongCarryingEdge(problem, layout, z, options, scales, ejection_energy, workspace,
                                state, result, select);
}

std::vector<int> Carrying(const VectorXd& z, int first, int count) {
  const double largest = z.segment(first, count).maxCoeff();
  std::vector<int> carrying;
  for (int i = 0; i < count; ++i)
    if (z[first + i] > kCarryingFraction * largest) carrying.push_back(i);
  return carrying;
}

int StalledContact(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                   const IslandScales& scales) {
  VectorXd F;
  EvaluateIslandMncp(problem, layout, z, &F, nullptr);
  const VectorXd row_scale = IslandRowScales(problem, layout, scales);
  const VectorXd var_scale = IslandVariableScales(problem, layout, scales);
  int worst = 0;
  double worst_residual = -1;
  for (size_t k = 0; k < layout.contacts.size(); ++k) {
    ScaledRowResidual r(layout.num_free, z, F, row_scale, var_scale);
    r.AddContact(layout.contacts[k], 1);
    if (r.value() > worst_residual) {
      worst_residual = r.value();
      worst = static_cast<int>(k);
    }
  }
  return worst;
}

bool SolveOnCarryingFaces(const IslandProblem& problem, const IslandLayout& layout,
                          const VectorXd& z, McpOptions& options, const IslandScales& scales,
                          double ejection_energy, StepWorkspace& workspace, IslandState& state,
                          AdvanceResult& result, const RootSelector& select) {
  if (!z.allFinite()) return false;
  IslandProblem reduced = problem;
  bool cut = false;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const MncpLayout::Contact& L = layout.contacts[k];
    if (!(z.segment(L.l, L.l_count).maxCoeff() > 0)) continue;
    std::vector<int> carrying;  // stays sorted, as windows are
    for (int i : Carrying(z, L.l, L.l_count)) carrying.push_back(problem.contacts[k].window[i]);
    cut |= carrying.size() < problem.contacts[k].window.size();
    reduced.contacts[k].window = std::move(carrying);
    // a moving G's constraints alike: a finger's cap rim weakly active beside its side
    if (problem.contacts[k].other_kind == Other::kFixed) continue;
    if (!(z.segment(L.l_g, L.l_g_count).maxCoeff() > 0)) continue;
    std::vector<int> carrying_g;
    for (int j : Carrying(z, L.l_g, L.l_g_count))
      carrying_g.push_back(problem.contacts[k].other_window[j]);
    cut |= carrying_g.size() < problem.contacts[k].other_window.size();
    reduced.contacts[k].other_window = std::move(carrying_g);
  }
  if (!cut) return false;
  const IslandLayout reduced_layout = MakeIslandLayout(reduced);
  VectorXd rz = RemapWindows(problem, layout, z, reduced, reduced_layout);
  const Attempt attempt = SolveAttempt(reduced, reduced_layout, rz, options, scales,
                                       ejection_energy, workspace, result);
  return AcceptReduced(reduced, reduced_layout, rz, attempt, scales, state, result, select);
}

bool SolveAtDegenerateVertex(const IslandProblem& problem, const IslandLayout& layout,
                             const VectorXd& z, McpOptions& options, const IslandScales& scales,
                             double ejection_energy, StepWorkspace& workspace, IslandState& state,
                             AdvanceResult& result, int depth, const RootSelector& select) {
  if (depth == 0 || !z.allFinite()) return false;
  const int stalled = layout.num_bodies > 1 ? StalledContact(problem, layout, z, scales) : -1;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    if (stalled >= 0 && static_cast<int>(k) != stalled) continue;
    const MncpLayout::Contact& L = layout.contacts[k];
    const double largest = z.segment(L.l, L.l_count).maxCoeff();
    std::vector<int> active;  // indices into the window, by increasing multiplier
    for (int i = 0; i < L.l_count; ++i)
      if (z[L.l + i] > kDegenerateActiveFraction * largest) active.push_back(i);
    if (active.size() < 4) continue;
    std::sort(active.begin(), active.end(), [&](int a, int b) { return z[L.l + a] < z[L.l + b]; });
    for (size_t drop = 0; drop + 3 < active.size(); ++drop) {
      IslandProblem reduced = problem;
      std::vector<int>& window = reduced.contacts[k].window;
      window.erase(window.begin() + active[drop]);
      const IslandLayout reduced_layout = MakeIslandLayout(reduced);
      VectorXd rz = RemapWindows(problem, layout, z, reduced, reduced_layout);
      const Attempt attempt = SolveAttempt(reduced, reduced_layout, rz, options, scales,
                                           ejection_energy, workspace, result);
      const bool can_reach_three = active.size() <= static_cast<size_t>(3 + depth);
      if (attempt.outcome == Outcome::kUnconverged && can_reach_three &&
          SolveAtDegenerateVertex(reduced, reduced_layout, rz, options, scales, ejection_energy,
                                  workspace, state, result, depth - 1, select)) {
        return true;
      }
      if (AcceptReduced(reduced, reduced_layout, rz, attempt, scales, state, result, select)) {
        return true;
      }
    }
  }
  return false;
}

bool SolveAlongCarryingEdge(const IslandProblem& problem, const IslandLayout& layout,
                            const VectorXd& z, McpOptions& options, const IslandScales& scales,
                            double ejection_energy, StepWorkspace& workspace, IslandState& state,
                            AdvanceResult& result, const RootSelector& select) {
  if (!z.allFinite()) return false;
  const int stalled = layout.num_bodies > 1 ? StalledContact(problem, layout, z, scales) : -1;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    if (stalled >= 0 && static_cast<int>(k) != stalled) continue;
    if (SolveAlongEdgeOf(static_cast<int>(k), problem, layout, z, options, scales, ejection_energy,
                         workspace, state, result, select)) {
      return true;
    }
  }
  return false;
}

}  // namespace ecpsim::engine::hull
