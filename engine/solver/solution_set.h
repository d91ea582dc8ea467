#pragma once
// Where a mixed complementarity problem's solutions form a set, not a point: the set's
// directions at a solution, and the point of the set where an energy is least — the second
// stage of the selection rule for statically indeterminate contact (engine/README.md, "Steps
// whose solutions form a set").

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "engine/solver/complementarity_solver.h"

namespace ecpsim::engine {

/// The directions (orthonormal columns, in the scaled unknowns x = z / var_scale) along which the
/// solutions of the MCP (num_free, F; SolveMcp's convention) continue from a solution z, to first
/// order. In the scaled problem F̃ = row_scale ⊙ F, with `tolerance` the solve's measure, each
/// unknown is held as its row says: a free row keeps F̃_i = 0; a complementarity pair with
/// x_i > tolerance is active and keeps F̃_i = 0, one with F̃_i > tolerance inactive and keeps
/// x_i = 0, and a degenerate one (both ≤ tolerance) keeps both. The directions are the null space
/// of those rows' matrix (J's rows scaled, and unit rows): the kernel of the held rows of J on the
/// unknowns not held at 0, its rank set by a fully pivoted LU's pivots above
/// kMinimumNormRankTolerance of the largest, as SolveMcp's minimum-norm steps set it by their
/// decomposition's. Empty where z is an isolated solution.
///
/// `ties` (empty, or one entry per unknown): ties[i] = j ≥ 0 holds unknown i as it is wherever
/// unknown j is held at 0 (its pair inactive or degenerate), and leaves row i out; where j moves,
/// row i is divided by its largest entry, its scale being j's state's, not the problem's. A
/// contact's friction impulses and σ are tied to its normal impulse p_n: at p_n = 0 the cone
/// μ² p_n² − |p|² ≥ 0 holds p at 0 to second order only, which J does not see, and with p = 0 the
/// friction rows hold for any slip and any σ (FORMULATION.md trap 2); at p_n > 0 their entries go
/// with p_n and σ. Untied, an unloaded contact would let the friction of a load it does not bear
/// move along the set.
Eigen::MatrixXd SolutionSetDirections(const Eigen::MatrixXd& J, const Eigen::VectorXd& z,
                                      const Eigen::VectorXd& F, int num_free,
                                      const Eigen::VectorXd& row_scale,
                                      const Eigen::VectorXd& var_scale, double tolerance,
                                      const std::vector<int>& ties = {});

/// E(z) = ½ ‖r(z)‖², the energy the selection minimizes over the solutions: the callback returns
/// the residuals r(z) and, when R is not null, their Jacobian ∂r/∂z (unscaled z; any number of
/// residuals).
using EnergyResiduals =
    std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd* r, Eigen::MatrixXd* R)>;

struct SelectionResult {
  bool converged = false;  // z is a solution (the measure ≤ options.tolerance), moved or not
  // the set's dimension at the given solution, its degenerate pairs held (0 with no pair to let
  // go: isolated, z untouched)
  int directions = 0;
  int steps = 0;            // steps taken along the set
  double start_energy = 0;  // E at the given solution ...
  double energy = 0;        // ... and at the returned one
  // the complementarity unknowns i whose pair is degenerate at the returned solution (x_i and
  // F̃_i both ≤ tolerance: a pair on the edge of its set, such as friction at its limit unslipped)
  std::vector<int> degenerate;
};

/// Moves a solution z of the MCP along its set of solutions to the point where E is least.
/// Each step is the Gauss–Newton step of E restricted to the set's directions at z (the least-
/// squares solution of (R N) d = −r), with a degenerate pair let go on one side (its x_i or its
/// F̃_i free to grow) where the held rows' multipliers say that lowers E, and the step solved
/// again until none does (an active set over the pairs' one-sided holds), cut to keep every
/// active pair's x_i ≥ 0, followed by minimum-norm Newton steps back onto the set (SolveMcp with
/// `options`, minimum_norm_steps and kNearSetStallIterations: the nearest solution, nothing moved
/// along the set); it is taken where it lands on a solution whose E is not higher (to
/// round-off), else halved (up to kSelectionHalvings times), and changed to the secant root of
/// E's slope along it where that lands closer to E's least point (a curved set). The steps end
/// when the Gauss–Newton step is below `options.tolerance` in the scaled unknowns, or after
/// kMaxSelectionSteps. Where z is isolated — or is no solution — z is left exactly as it is. A
/// strictly convex E on a convex set gives one point whatever solution of the set z was. The
/// set's directions are SolutionSetDirections' with `ties`.
SelectionResult SelectLeastEnergySolution(const McpFunction& f, int num_free,
                                          const Eigen::VectorXd& row_scale,
                                          const Eigen::VectorXd& var_scale,
                                          const EnergyResiduals& energy, Eigen::VectorXd& z,
                                          const McpOptions& options, McpWorkspace& workspace,
                                          const std::vector<int>& ties = {});

/// The bound on the steps along the set: Gauss–Newton on a quadratic E over a flat set ends in
/// one, a curved set (the ECP on a cylinder's rim) in a few more.
inline constexpr int kMaxSelectionSteps = 20;
/// The halvings of a step that did not lower E (a curved set's Gauss–Newton step overshoots).
inline constexpr int kSelectionHalvings = 8;
/// Iterations without halving the residual before a solve from a start next to the set gives up
/// (McpOptions::stall_iterations): a landing starts a second-order distance off the set, the
/// selection's first solve a creep's or a step's change (hull::SelectLeastEnergyRoot), and Newton
/// gets there in a few iterations where it gets there at all; a solve that has not, runs its whole
/// budget for nothing before the step is halved. Fewer stopped slow landings that do get there,
/// and the selection ended short of its least point (LeastEnergyPointTest; a centred grip turning
/// as it slips, tests/python/test_grasp_slip.py).
inline constexpr int kNearSetStallIterations = 20;

}  // namespace ecpsim::engine
