#pragma once
// decomposition: auto — per pair and step, the one contact of the hulls where it is exact, the
// contacts of the parts where something can reach into a cavity (engine/README.md, "Bodies made
// of convex parts").

#include "engine/broad_phase.h"
#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// How far (× the body's hull diagonal) inside a body's hull a point of the other body must be
/// to be in its cavity: far above the round-off of a point on the hull's face (1e-15) and of a
/// contact's converged gap (1e-12), far below any modelled feature.
inline constexpr double kInsideHullRelTolerance = 1e-9;

/// Whether the contacts of the hulls (SideChoice::kHulls) of the pair of contact `k` (a pair
/// that lists both sets) are exact over the step from `state`: for each of its bodies under
/// Decomposition::kAuto, the other's hull (or the obstacle) neither comes within the step's
/// reach (`reach`, both bodies' distances) of one of its lids nor has its point nearest the body
/// inside the body's hull by more than kInsideHullRelTolerance — it is then outside the hull and
/// can touch it only where the hull is the body's own surface. Lids whose world boxes, grown by
/// their body's reach, miss the other's step box (StepReach::boxes) are out of reach without GJK;
/// against a kinematic body, whose reach is its box alone, every other lid is reached. Never
/// where the kinematic body is itself under kAuto (its lids move within the step).
bool HullsExact(const Scene& scene, const State& state, const StepReach& reach, int k);

}  // namespace ecpsim::engine
