#pragma once
// The multi-patch model's warm start made consistent with the step's own equations where a body
// slides flat on one plane on several parts (the desk's four feet; engine/README.md, "The
// multi-patch model", "A balanced warm start"): the hull model's sliding balance on the parts'
// summed wrench, then the parts' loads split so that their combined ECP is the balanced one.

#include <Eigen/Core>

#include "engine/models/balanced_start.h"
#include "engine/models/multipatch_model.h"

namespace ecpsim::engine {

/// Balances, in z, the warm start of a body sliding flat on one plane on several parts: one
/// group of at least two blocks, each on the plane, pressed (p_n,i > 0), sliding (σ_i > 0) and
/// carried by one face of its part (its multiplier alone above `active_fraction` of the part's
/// largest). Each part's ECP is carried with the body from the start of the step (where the
/// last step left it, on the part) to the end of this one; the parts' summed wrench at their
/// combined ECP is balanced by SweepSlidingBalance (the velocities, p_n, the friction at the
/// group's slip and the combined ECP the torque rows ask for); the parts' normal impulses are
/// then the warm start's changed least (in the 2-norm) to that total p_n and a load-weighted
/// mean of the carried ECPs at that combined ECP, and each part takes its share of the friction:
/// (p_t,i, p_o,i, p_rE,i) = (p_n,i / p_n) (p_t, p_o, p_r), σ_i = σ (engine/README.md, "Why it
/// agrees with the hull model on the desk": a solution of the multi-patch MNCP where the sweeps'
/// is one of the single-patch rows). The sweeps go to kMultiPatchBalanceTolerance (kBalanced)
/// and on to kPolishTolerance where they still contract (kPolished); z is left as it came
/// (kUnbalanced) where this does not apply, where the sweeps do not balance
/// (SweepSlidingBalance), or where the split would leave a part without load (the combined ECP
/// outside the parts' ECPs).
StartBalance BalanceMultiPatchSlidingStart(const MultiPatchProblem& problem,
                                           const MncpLayout& layout, double active_fraction,
                                           Eigen::VectorXd& z);

/// The sweeps' tolerance here (SweepSlidingBalance), tighter than the hull model's
/// kBalanceTolerance: near the parts' non-isolated solutions the proximal Newton step
/// (AddProximalTerms) removes less of a start's residual than the hull model's step does.
/// Measured without the polish, which it is the fallback of (with it no desk step after the
/// first takes a Newton step), on the desk (`ecpsim run scenes/desk.yaml --model multipatch`,
/// 399 balanced warm starts; the steps' Newton iterations 1 / 2 / 3 and the largest end residual,
/// tolerance 1e-12): 1e-6
/// 357 / 39 / 3, 1e-8 359 / 37 / 3; 1e-9 one iteration every step but ending at up to 8.8e-13;
/// 1e-10 one every step (3 starts taken without a Newton step, under kBalancedStartAcceptance
/// of the tolerance), ending at ≤ 7.2e-14; 1e-11 and 1e-12 the same ends, with 19 and 26 starts
/// taken as they are.
inline constexpr double kMultiPatchBalanceTolerance = 1e-10;

}  // namespace ecpsim::engine
