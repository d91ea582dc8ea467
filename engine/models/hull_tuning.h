#pragma once
// The hull model's tuning constants, each with what it guards (engine/README.md, "Restart
// ladder" and its subsections); the measurements behind each value are in the git history of
// this file and of hull_model.cpp.

#include <cmath>

namespace ecpsim::engine::hull {

// a guess's slip multiplier starts slightly positive, of the velocity scale: (σ, ζ) = (0, 0) is
// the kink of φ_FB
inline constexpr double kInitialSigmaFraction = 1e-3;
// the window check's tolerance, of the body's size: far below any face, far above round-off
inline constexpr double kWindowCheckRelTol = 1e-9;
// rad: the largest turn h|ω⁺| of one step; beyond π the end pose is reached by a smaller turn
// too, so such a root is an alias ("Impacts")
inline constexpr double kMaxStepRotation = M_PI;
// a converged step may gain at most this fraction of the energy scale m V² + |p_ext| L / h
// beyond the loads' work: the implicit step dissipates O(h²); spurious roots gained 1.6e-2 and
// more ("Roots that gain energy")
inline constexpr double kMaxEnergyGainRel = 1e-3;
// the solver's Jacobian smoothing per unit of ‖Φ‖ (McpOptions): the value that solved the most
// of the drop sweep's failing steps (0.01 and 1 solved fewer)
inline constexpr double kJacobianSmoothing = 0.1;
// iterations without halving the residual before a solve gives up for the next guess: Newton
// halves it every iteration near a root, the slowest recoveries seen went 30 without
inline constexpr int kStallIterations = 45;
// the same for a body alone's warm start in the first pass, whose stall the later guesses take
// over: converged warm starts went up to 25 ("The first pass's warm start")
inline constexpr int kWarmStartStallIterations = 15;
// the same for the predicted start: converging ones took 2–4 iterations, stalling ones 6–14
// ("The predicted start")
inline constexpr int kPredictedStallIterations = 5;
// a resting contact sticks where σ is at most this fraction of the velocity scale: Newton
// leaves a sticking σ at round-off, far below it (balanced_start.h)
inline constexpr double kStickingSlipFraction = 1e-12;
// the predicted start follows only a trend whose second difference of the velocity is below
// this fraction of its first: an event within the trend makes them alike (1.2–1.6 measured at
// landings, 0.01–0.12 along smooth rocking)
inline constexpr double kMaxTrendBend = 0.5;
// ... or below this fraction of the velocity scale: a body rolling almost uniformly bends its
// trend more than its first difference, and its predicted starts converge
inline constexpr double kNegligibleBend = 1e-3;
// a hull point that the last velocities take deeper than the last ECP by this fraction of the
// body's length marks a landing on another feature, where the sliding guess goes first
// ("Landings"; fewest Newton iterations between 0.01 and 0.02)
inline constexpr double kLandingDip = 0.02;
// the last resort's iteration budget per guess, in solver budgets: on a solution set that ends
// at a degenerate pair Newton converges linearly (a finger's first touch took up to 3 budgets)
inline constexpr int kPlainNewtonBudgetFactor = 4;
// a face multiplier above this fraction of the contact's largest is active at a degenerate
// vertex: far above round-off, below the smallest carrying multiplier seen (1.9e-6)
inline constexpr double kDegenerateActiveFraction = 1e-9;
// a face multiplier below this fraction of the contact's largest carries nothing measurable:
// weakly active faces at a stall measured 1e-9 … 1e-12 beside carrying ones of 0.4
inline constexpr double kCarryingFraction = 1e-6;
// faces left out at most at a degenerate vertex: six faces come down to three; deeper, the tree
// of drops grows as n³ ("Degenerate vertices")
inline constexpr int kMaxDegenerateDrops = 3;
// starts spread along a stalled contact's edge ("Stalls on an edge"): their spacing is a
// sixteenth of the hull's extent along the edge
inline constexpr int kEdgeStarts = 16;
// a start-of-step overlap of two hulls below this fraction of F's size is a resting contact's
// round-off: its ejection energy is negligible, no GJK query is made
inline constexpr double kNegligibleDepthRel = 1e-9;
// an island of several bodies is re-solved on fewer faces only when it stalled within this
// factor of the tolerance: degenerate vertices stall 10–100 × above it
inline constexpr double kMaxDegenerateStall = 1e4;
// a body alone is re-solved at once within this factor: stalls on an edge measured up to 2e5 ×,
// while stalls that are no root's neighbour sit 1e9 × above ("Which stalls are re-solved")
inline constexpr double kMaxOneBodyStall = 1e7;
// window growths before a guess counts as failed: one is what a solution past the window's rim
// needs, the rest is margin; a step never falls back to every face ("Large hulls: the window")
inline constexpr int kMaxWindowGrowth = 6;
// an island of several bodies with at least this many unknowns is solved with a sparse
// Jacobian, smaller ones dense: the dominoes' fastest split ("The island's linear algebra")
inline constexpr int kMinSparseUnknowns = 200;
// the minimum-norm passes factor their Newton matrix dense, O(n³) an iteration: beyond this size
// they are left out. On the nine dominoes' pile (372 … 540 unknowns) they took two thirds of the
// run's CPU (about 16 ms an iteration at 540, 7 × the sparse LU's) and solved 3 of 67 attempts,
// steps that the proximal passes then solve; the pile of five (DominoesTest, ≤ 300) settles by them
inline constexpr int kMaxMinimumNormUnknowns = 300;
// the proximal pass's ε (McpOptions::proximal_weight) against the scaled Newton matrix's O(1)
// entries: far above their round-off, and a rate of 1e-6 per iteration along the determined
// directions. On the dominoes' landings 1e-6 took 25 % less CPU than 1e-8 ("Non-isolated
// solutions")
inline constexpr double kProximalWeight = 1e-6;

}  // namespace ecpsim::engine::hull
