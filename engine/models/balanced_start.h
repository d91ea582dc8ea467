#pragma once
// The hull model's starts made consistent with the step's own equations where they are off
// (engine/README.md, "Balanced starts"): of a body alone on fixed obstacles, its start where it
// slides flat (predicted, warm or the sliding guess), its warm start where it rests under loads
// that changed, the multipliers of the faces that carry it where it rocks — at the cost of a few
// 3 × 3 solves instead of Newton iterations.

#include <Eigen/Core>

#include "engine/mncp/island_mncp.h"

namespace ecpsim::engine {

/// Whether exactly one hull face carries contact `L` in z: one multiplier l exceeds
/// `active_fraction` of the contact's largest (a body flat on its face, not on an edge or vertex).
bool CarriedByOneFace(const MncpLayout::Contact& L, double active_fraction,
                      const Eigen::VectorXd& z);

/// Refits, in z, the multipliers of the hull faces that carry each contact of a body alone on
/// fixed obstacles (an edge's two, a vertex's three: those whose multiplier exceeds
/// `active_fraction` of the contact's largest) to z's pose and ECP: the least-squares l of the
/// normal-cone rows N + Σ l_i R⁺ ∇f_i = 0 over those faces. A contact carried by one face, or
/// whose fit comes out ≤ 0 or non-finite, keeps its l.
void FitCarryingMultipliers(const IslandProblem& problem, const IslandLayout& layout,
                            double active_fraction, Eigen::VectorXd& z);

/// A body sliding flat on one plane, as the sliding balance's sweeps see it: its velocities
/// (m/s, rad/s, world), the ECP (m, world), the friction impulse (p_t, p_o, p_r) in the plane's
/// contact frame (N·s, N·m·s), p_n (N·s) and σ = ‖(e_t v_t, e_o v_o, e_r v_r)‖ (m/s).
struct SlidingBalance {
  Eigen::Vector3d v, w, a1, friction;
  double p_n = 0, slip_norm = 0;
};

/// What SweepSlidingBalance does with a start whose friction already agrees with its slip.
enum class AgreeingStart {
  kKeep,   // a start whose friction agrees is exact (a trend's prediction of a uniform slide)
  kSweep,  // it may be off in the other rows all the same (a warm start under changed loads)
};

/// The sweeps of BalanceSlidingStart on one body (its Newton–Euler rows) and one contact wrench
/// at `balance.a1` on the plane of `frame` (n its normal), until the friction impulse changes by
/// at most `tolerance` of μ p_n: friction at maximum dissipation of the slip, the tangential
/// velocity and p_n from the force rows (the normal velocity kept), the turn about n and the
/// ECP's shift in the plane from the torque rows; at least two sweeps (the first one's friction
/// is the start's slip's). Returns whether `balance` was balanced; it is left as it came where
/// the sweeps do not contract, the slip vanishes or p_n would be ≤ 0, and with
/// AgreeingStart::kKeep where the start's friction already agrees with its slip to `tolerance`.
bool SweepSlidingBalance(const BodyProblem& body, const ContactFrame& frame, const Friction& fr,
                         double tolerance, AgreeingStart agreeing, SlidingBalance& balance);

/// How far a balance took a start.
enum class StartBalance {
  kUnbalanced,  // it was left as it came
  kBalanced,    // to kBalanceTolerance: one Newton step takes it to round-off
  kPolished,    // on to kPolishTolerance: usually a solution to round-off already
};

/// SweepSlidingBalance to `tolerance` (kBalanced), then on to kPolishTolerance where the sweeps
/// still contract there (kPolished); `balance` is left as it came where the first sweeps do not
/// balance it (kUnbalanced).
StartBalance SweepAndPolish(const BodyProblem& body, const ContactFrame& frame, const Friction& fr,
                            double tolerance, AgreeingStart agreeing, SlidingBalance& balance);

/// Balances, in z, a start of one body sliding flat on one plane (one hull face carries the
/// contact: its multiplier alone exceeds `active_fraction` of the largest): sweeps that set the
/// friction impulses and σ to maximum dissipation at z's slip, the tangential velocity and p_n
/// to the Newton–Euler force rows (the normal velocity kept), and the turn about the plane's
/// normal with the ECP's place on the face to the torque rows, until the friction impulse
/// changes by at most kBalanceTolerance of μ p_n (kBalanced), and on where they still contract
/// until it changes by at most kPolishTolerance (kPolished). z is left as it came
/// (kUnbalanced) where the sweeps do not apply (not one body with one contact on a plane without
/// creep, flat and sliding with σ > 0), where its friction already agrees with its slip to
/// kBalanceTolerance (an exact start: a prediction of a uniform deceleration), or where the
/// sweeps do not contract (a slip too slow for its friction: the fixed point of slip and
/// friction diverges there) or would make p_n ≤ 0.
StartBalance BalanceSlidingStart(const IslandProblem& problem, const IslandLayout& layout,
                                 double active_fraction, Eigen::VectorXd& z);

/// Balances, in z, the warm start of one body at rest flat on one plane (one hull face carries
/// the contact, σ ≤ `sticking_slip` m/s, the slip's round-off: sticking) to loads that changed
/// since it was solved: with z's velocities, the contact force (p_n, p_t, p_o) from the
/// Newton–Euler force rows, and p_r with the ECP's place on the face from the torque rows (a
/// linear 3 × 3 solve). Returns whether z was balanced; z is left as it came where this does not
/// apply (not one body with one contact on a plane without creep, flat and sticking with
/// p_n > 0), where the loads did not change (the balance would move z by its round-off only:
/// kUnchangedFraction in balanced_start.cpp), or where the balanced friction leaves the friction
/// ellipsoid (the body starts to slide: the Newton iteration finds how).
bool BalanceRestingStart(const IslandProblem& problem, const IslandLayout& layout,
                         double active_fraction, double sticking_slip, Eigen::VectorXd& z);

/// A balanced start ends the step without a Newton step only at this fraction of the solver's
/// tolerance (McpOptions::start_tolerance): the hull model's balanced predicted start met the
/// tolerance in 118 of the desk's 400 steps, at up to 9.5e-13 against 1e-12, and accepting it
/// there moved the desk's trajectory by 9.5e-11 m/s; one Newton step from it ends at 1e-16
/// (C r² with C ≈ 26), where the steps from the unbalanced start ended, and the trajectory stays
/// within 1.3e-14 m/s of theirs. A slide's uniform deceleration, which the trend extrapolates
/// exactly, starts at round-off (≤ 1e-14) and still ends there without a Newton step (1e-3 gave
/// it 8 steps more of 24 over its run).
inline constexpr double kBalancedStartAcceptance = 1e-2;
/// The same for a polished start (kPolishTolerance), whose measure is the round-off of its rows
/// rather than a mismatch the sweeps left: on the engine benchmark's desk (BM_DeskStep, the desk
/// built in code, whose face rows' round-off is larger than scenes/desk.yaml's) polished starts
/// measured 1.0e-14 … 5.2e-14 in 40 % of the steps, which 1e-2 sent to a Newton step each
/// (0.60 iterations a step; 1e-1: 0.0075); on scenes/desk.yaml 1e-2 and 1e-1 both took none
/// after the first step. The trajectories moved by round-off: the desk by 1.8e-14 m/s, the
/// T-bar by 2.1e-12 m/s (1.1e-13 with 1e-2; its run 904 iterations instead of 866).
inline constexpr double kPolishedStartAcceptance = 1e-1;

/// The sweeps stop when the friction impulse changed by at most this fraction of μ p_n. On the
/// paper's desk (scenes/desk.yaml) the one Newton step from the balanced start then ends at
/// 6e-17 … 1.7e-16 (the unbalanced start's two ended at 1e-16 too), after 3–4 sweeps; 1e-5 left
/// ends at up to 9.5e-15 and the trajectory 5e-14 m/s off, 1e-7 … 1e-10 took up to 5 … 8 sweeps
/// for the same ends (engine/README.md, "Balanced starts").
inline constexpr double kBalanceTolerance = 1e-6;
/// The polish: BalanceSlidingStart's sweeps go on from kBalanceTolerance to this change of the
/// friction impulse (of μ p_n) where they still contract, a few sweeps more, and the start then
/// usually solves the step to round-off. Measured with kPolishedStartAcceptance = 1e-1 (`ecpsim
/// run scenes/X.yaml --model hull`, Newton iterations per run, against 402 and 957 without the
/// polish, and the largest change of a position or velocity): 1e-11 left the desk 3 (all in
/// its first step, which has no trend to start from) at 4.4e-14 m/s, the T-bar 901 at
/// 1.5e-12; 1e-12 the desk 3 at 1.8e-14, the T-bar 866 at 2.1e-12; 1e-13 the desk 3 at
/// 6.4e-15, the T-bar 886 at 1.9e-12. Below, the sweeps stall at their round-off and the
/// polish is given up.
inline constexpr double kPolishTolerance = 1e-12;
inline constexpr int kMaxBalanceSweeps = 12;

/// The start tolerance (McpOptions::start_tolerance) of a start balanced as `balance`, for the
/// solver's `tolerance`: none (∞) unbalanced, else kBalancedStartAcceptance or
/// kPolishedStartAcceptance of it.
double BalancedStartTolerance(StartBalance balance, double tolerance);

}  // namespace ecpsim::engine
