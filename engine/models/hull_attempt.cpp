#include "engine/models/hull_attempt.h"

#include <algorithm>

#include <fmt/format.h>

#include "engine/mncp/contact_window.h"
#include "engine/mncp/mncp_system.h"
#include "engine/models/hull_tuning.h"
#include "engine/models/solution_trend.h"
#include "engine/rotation.h"

namespace ecpsim::engine::hull {

using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

std::string Attempt::Describe() const {
  const char* what = outcome == Outcome::kAliased       ? "aliased rotation, residual"
                     : outcome == Outcome::kGainsEnergy ? "energy gain, residual"
                                                        : "residual";
  return fmt::format("{} {:.3g} after {} iterations", what, residual, iterations);
}

Attempt SolveAttempt(const IslandProblem& problem, const IslandLayout& layout, VectorXd& z,
                     McpOptions& options, const IslandScales& scales, double ejection_energy,
                     StepWorkspace& workspace, AdvanceResult& result) {
  // what the callbacks need, captured by one reference: std::function keeps a lambda that
  // small in place instead of allocating it on every solve
  struct Context {
    const IslandProblem& problem;
    const IslandLayout& layout;
    const VectorXd& row_scale;
    const VectorXd& var_scale;
    const IslandResidualUnits& units;
  };
  // (the scales' storage kept in the workspace from solve to solve: no solve runs inside another)
  struct Scaling {
    VectorXd row_scale, var_scale;
    IslandResidualUnits units;
  };
  Scaling& scaling = workspace.Part<Scaling>();
  McpWorkspace& solver_workspace = workspace.Part<McpWorkspace>();
  IslandRowScales(problem, layout, scales, scaling.row_scale);
  IslandVariableScales(problem, layout, scales, scaling.var_scale);
  MakeIslandResidualUnits(problem, scales, options.tolerance, scaling.units);
  const Context c{problem, layout, scaling.row_scale, scaling.var_scale, scaling.units};
  options.measure = [&c](const VectorXd& zz, const VectorXd& F) {
    return IslandMncpResidual(c.problem, c.layout, zz, F, c.row_scale, c.var_scale, c.units);
  };
  McpResult solve;
  if (layout.num_bodies > 1 && layout.size >= kMinSparseUnknowns) {
    const SparseMcpFunction f = [&c](const VectorXd& zz, VectorXd* F, SparseMatrix* J) {
      EvaluateIslandMncpSparse(c.problem, c.layout, zz, F, J);
    };
    solve = SolveMcp(f, layout.num_free, c.row_scale, c.var_scale, z, options, solver_workspace);
  } else {
    // SolveMcp hands J over zero (complementarity_solver.h)
    const McpFunction f = [&c](const VectorXd& zz, VectorXd* F, Eigen::MatrixXd* J) {
      EvaluateIslandMncp(c.problem, c.layout, zz, F, J, /*jacobian_is_zero=*/true);
    };
    solve = SolveMcp(f, layout.num_free, c.row_scale, c.var_scale, z, options, solver_workspace);
  }
  options.measure = nullptr;
  result.iterations += solve.iterations;
  Attempt attempt;
  attempt.residual = solve.residual;
  attempt.iterations = solve.iterations;
  if (!solve.converged || !z.allFinite()) return attempt;
  // a turn of more than π in one step is an alias: Exp(hω⁺) has the same end pose for a
  // smaller ω⁺, so such a root of the MNCP is a spurious one (it can gain energy); so is one
  // that gains energy the applied loads did not give (engine/README.md, "Roots that gain
  // energy"): the contact can only take energy away
  bool aliased = false;
  for (int b = 0; b < layout.num_bodies; ++b)
    aliased |= problem.h * z.segment<3>(IslandLayout::Velocity(b) + 3).norm() > kMaxStepRotation;
  if (aliased) {
    attempt.outcome = Outcome::kAliased;
  } else if (IslandStepEnergyGain(problem, layout, z) >
             kMaxEnergyGainRel * IslandEnergyScale(problem, scales) + ejection_energy) {
    attempt.outcome = Outcome::kGainsEnergy;
  } else {
    attempt.outcome = Outcome::kSolved;
  }
  return attempt;
}

bool GrowViolatedWindows(IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                         const IslandScales& scales) {
  bool grown = false;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const MncpLayout::Contact& L = layout.contacts[k];
    IslandContact& cp = problem.contacts[k];
    const int col = IslandLayout::Velocity(cp.body);
    const EndPose end =
        PoseAfterStep(problem.bodies[cp.body], z.segment<3>(col), z.segment<3>(col + 3));
    const double tolerance = kWindowCheckRelTol * scales.bodies[cp.body].length;
    int active = 0;
    z.segment(L.l, L.l_count).maxCoeff(&active);
    const Vector3d y = end.R.transpose() * (z.segment<3>(L.a1) - end.c);
    const std::vector<int> violated =
        WindowViolations(*cp.hull, cp.window, cp.window[active], y, tolerance);
    if (!violated.empty()) {
      cp.window = GrowWindow(*cp.hull, cp.window, violated);
      grown = true;
    }
    if (cp.other_kind == Other::kFixed) continue;
    const EndPose other = OtherEndPose(problem, z, static_cast<int>(k));
    int active_g = 0;
    z.segment(L.l_g, L.l_g_count).maxCoeff(&active_g);
    const Vector3d y_g = other.R.transpose() * (z.segment<3>(L.a2) - other.c);
    const std::vector<int> violated_g = WindowViolations(*cp.other_shape, cp.other_window,
                                                         cp.other_window[active_g], y_g, tolerance);
    if (!violated_g.empty()) {
      cp.other_window = GrowWindow(*cp.other_shape, cp.other_window, violated_g);
      grown = true;
    }
  }
  return grown;
}

void CommitSolution(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                    IslandState& state) {
  const double h = problem.h;
  // the contacts first: their trends start from the bodies' velocities before the step
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const MncpLayout::Contact& L = layout.contacts[k];
    const IslandContact& cp = problem.contacts[k];
    ContactState& c = state.contacts[k];
    const auto* last = c.warm_start.Get<HullWarmStart>();
    const SolutionTrend::Point before =
        TrendPoint(state.bodies[cp.body], c, last != nullptr ? last->s : 0.0);
    const ContactGap gap = ContactGapAt(L, cp.other_shape, z);
    c.a1 = z.segment<3>(L.a1);
    c.a2 = gap.a2;
    c.p_t = z[L.p_t];
    c.p_o = z[L.p_o];
    c.p_r = z[L.p_r];
    // complementarity unknowns are ≥ 0 up to the tolerance; report them clamped
    c.p_n = std::max(z[L.p_n], 0.0);
    // without a normal impulse any σ ≥ 0 solves the MNCP (trap 2); report the canonical 0
    c.sigma = c.p_n > 0 ? std::max(z[L.sigma], 0.0) : 0.0;
    const ContactFrame frame = MakeContactFrame(
        IslandContactNormal(problem, layout, z, static_cast<int>(k)), cp.tangent_reference);
    c.n = frame.n;
    c.t = frame.t;
    c.o = frame.o;
    BodyState after;
    after.v_WB = z.segment<3>(IslandLayout::Velocity(cp.body));
    after.w_WB = z.segment<3>(IslandLayout::Velocity(cp.body) + 3);
    const SolutionTrend trend =
        NextTrend(last != nullptr ? &last->trend : nullptr, before, TrendPoint(after, c, gap.s), h);
    // written over the last warm start, whose storage it reuses; on a plane l_G = 1 (its one
    // constraint)
    HullWarmStart& warm = last != nullptr ? *c.warm_start.Get<HullWarmStart>()
                                          : c.warm_start.Emplace<HullWarmStart>();
    warm.s = gap.s;
    if (L.on_plane()) {
      warm.l_g.setOnes(1);
    } else {
      warm.l_g = z.segment(L.l_g, L.l_g_count);
    }
    warm.window = cp.window;
    warm.l = z.segment(L.l, L.l_count);
    if (cp.other_kind != Other::kFixed) {
      warm.other_window = cp.other_window;
    } else {
      warm.other_window.clear();
    }
    warm.trend = trend;
  }
  for (int b = 0; b < layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    const Vector3d v = z.segment<3>(col);
    const Vector3d w = z.segment<3>(col + 3);
    BodyState& body = state.bodies[b];
    body.p_WB += h * v;
    body.Q_WB = IntegrateOrientation(body.Q_WB, w, h);
    body.v_WB = v;
    body.w_WB = w;
  }
}

SolutionTrend::Point HullTrendPoint(const BodyState& body, const ContactState& c) {
  const auto* warm = c.warm_start.Get<HullWarmStart>();
  return TrendPoint(body, c, warm != nullptr ? warm->s : 0.0);
}

void CommitFlatWarmStart(const SolutionTrend::Point& before, double h, const BodyState& body,
                         int face, ContactState& c) {
  auto* warm = c.warm_start.Get<HullWarmStart>();
  const SolutionTrend trend =
      NextTrend(warm != nullptr ? &warm->trend : nullptr, before, TrendPoint(body, c, 0.0), h);
  // written over the last warm start, whose storage it reuses
  if (warm == nullptr) warm = &c.warm_start.Emplace<HullWarmStart>();
  warm->s = 0;
  warm->l_g.setOnes(1);
  warm->window.assign(1, face);
  warm->l.setOnes(1);
  warm->other_window.clear();
  warm->trend = trend;
}

bool AcceptReduced(const IslandProblem& reduced, const IslandLayout& layout, const VectorXd& z,
                   const Attempt& attempt, const IslandScales& scales, IslandState& state,
                   AdvanceResult& result, const RootSelector& select) {
  if (attempt.outcome != Outcome::kSolved) return false;
  VectorXd root = z;
  if (select) select(reduced, layout, root);
  IslandProblem checked = reduced;
  if (GrowViolatedWindows(checked, layout, root, scales)) return false;
  CommitSolution(reduced, layout, root, state);
  result.residual = attempt.residual;
  return true;
}

}  // namespace ecpsim::engine::hull
