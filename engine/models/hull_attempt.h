#pragma once
// One solve of the hull model's island MNCP from a start, the checks a converged root must pass
// (no aliased rotation, no energy gained, every face outside the windows holding), and the
// commit of an accepted root to the island's state (engine/README.md, "Solver", "Roots that gain
// energy", "Impacts", "Large hulls: the window").

#include <functional>
#include <string>

#include <Eigen/Core>

#include "engine/contact_model.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/models/hull_warm_start.h"
#include "engine/models/solution_trend.h"
#include "engine/solver/complementarity_solver.h"
#include "engine/state.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine::hull {

/// How a solve ended: a root that passes the checks, no root, a root whose turn h|ω⁺| exceeds
/// kMaxStepRotation (an alias of a smaller turn), a root that gains energy the loads did not give.
enum class Outcome { kSolved, kUnconverged, kAliased, kGainsEnergy };

/// One solve of an island's MNCP from a start.
struct Attempt {
  Outcome outcome = Outcome::kUnconverged;
  double residual = INFINITY;  // the solver's convergence measure at its last iterate
  int iterations = 0;
  /// "residual 2.1e-09 after 60 iterations", with what was wrong with a root first.
  std::string Describe() const;
};

/// Solves the MNCP of `problem` (laid out as `layout`) from `z`, which it leaves at the last
/// iterate, with `options` (their measure is set for the solve and cleared after), dense or, for
/// an island of several bodies from kMinSparseUnknowns unknowns, sparse. A converged root is
/// checked: aliased where a body turns more than kMaxStepRotation in the step, gaining energy
/// where it gains more than kMaxEnergyGainRel of the island's energy scale plus
/// `ejection_energy` (J), working in `workspace`. Adds the solver's iterations to
/// `result.iterations`.
Attempt SolveAttempt(const IslandProblem& problem, const IslandLayout& layout, Eigen::VectorXd& z,
                     McpOptions& options, const IslandScales& scales, double ejection_energy,
                     StepWorkspace& workspace, AdvanceResult& result);

/// Grows the windows (F's, and a moving polyhedral G's) of every contact whose windowed solution
/// `z` violates a constraint left out, by kWindowCheckRelTol of its body's length
/// (contact_window.h); false when `z` solves the full-hull problem.
bool GrowViolatedWindows(IslandProblem& problem, const IslandLayout& layout,
                         const Eigen::VectorXd& z, const IslandScales& scales);

/// Writes the root `z` into the island's state: each contact's ECPs, impulses (complementarity
/// unknowns clamped at 0, σ 0 without a normal impulse), frame and warm start with its trend;
/// each body's pose advanced by its new velocities.
void CommitSolution(const IslandProblem& problem, const IslandLayout& layout,
                    const Eigen::VectorXd& z, IslandState& state);

/// A contact's point for its hull warm start's trend: TrendPoint with the warm start's gap s (0
/// without a hull warm start).
SolutionTrend::Point HullTrendPoint(const BodyState& body, const ContactState& c);

/// Writes the hull model's warm start of a contact that another model (the planar step) solved
/// flat on face `face` of F's hull against a plane: a1 = a2 (s = 0), the face's and the plane's
/// multipliers 1, and the trend carried on from `before` (HullTrendPoint before the step of
/// length h) to `body` and `c` after it, so that a hull step after it starts as after its own.
void CommitFlatWarmStart(const SolutionTrend::Point& before, double h, const BodyState& body,
                         int face, ContactState& c);

/// What the step does to a root it accepts, before the window check and the commit (the
/// least-energy selection, hull_selection.h); empty: nothing.
using RootSelector =
    std::function<void(const IslandProblem&, const IslandLayout&, Eigen::VectorXd&)>;

/// Commits the root of a problem whose windows were cut (faces left out) where it converged and
/// passed its checks and every face outside its windows holds (after `select`): then it is exact.
/// Sets `result.residual` to the attempt's.
bool AcceptReduced(const IslandProblem& reduced, const IslandLayout& layout,
                   const Eigen::VectorXd& z, const Attempt& attempt, const IslandScales& scales,
                   IslandState& state, AdvanceResult& result, const RootSelector& select = {});

}  // namespace ecpsim::engine::hull
