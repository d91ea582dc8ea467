#pragma once
// Sleeping islands (engine/README.md, "Sleeping islands"): an island that has ended its steps at
// rest, with its contacts and loads unchanged, replays its last step instead of solving it — its
// bodies keep their velocities, its contacts their solutions and warm starts, and only the poses
// advance — until a contact, a load or a kinematic body wakes it. The memory of the rule is
// State::rest (RestRecord).

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

// a body is at rest when it moves less than this fraction of its length per step, h |v| ≤ κ L and
// h |ω| L ≤ κ L: bodies resting on the shipped scenes move 1e-16 … 4e-16 L a step, and a replay
// and the awake step then differ by at most 2κ L a step (2e-12 L over 1,000) whatever their
// velocities' round-off
inline constexpr double kRestFraction = 1e-15;
// steps an island must end at rest before it sleeps: the hull warm start's trend (two differences,
// "The predicted start") then holds only steps at rest, and a landing's settling is over
inline constexpr std::int64_t kStepsToSleep = 10;
// a sleeping island is solved by its model on every 32nd step of its rest (and keeps sleeping if
// that step ends at rest): what the wake rules cannot see — round-off the replay does not redo —
// is then repaired within 32 steps, at 1/32 of the cost of staying awake
inline constexpr std::int64_t kSleepCheckSteps = 32;

/// Calls f(k) for each k, in order, where the flags `a` and `b` (one per contact of the scene,
/// equal sizes) differ: blocks that agree are passed over by memcmp, so that what a step pays per
/// potential pair of the scene (500,500 for 1,000 bodies) is a comparison of bytes in bulk.
template <class F>
void ForEachDifference(const std::vector<char>& a, const std::vector<char>& b, F&& f) {
  constexpr std::size_t kBlock = 256;
  const std::size_t n = a.size();
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const std::size_t end = std::min(n, begin + kBlock);
    if (std::memcmp(a.data() + begin, b.data() + begin, end - begin) == 0) continue;
    for (std::size_t k = begin; k < end; ++k)
      if (a[k] != b[k]) f(k);
  }
}

/// Whether `state` moves less than kRestFraction of `body`'s length (its radius of gyration) in a
/// step of `h` seconds, by its translation and by its rotation alike.
bool AtRest(const Body& body, const BodyState& state, double h);

/// The sleep rule's decision for each island of a step, made at its start.
struct SleepPlan {
  // per island: the rule's preconditions hold — sleeping on (solver.sleep), every body at rest at
  // the start, no body touched by a contact that entered or left the step since the last one, no
  // kinematic body in its contacts, no gripper jaw, and each body's applied impulse (loads,
  // impulses) over this step equal to its last step's, bit for bit
  std::vector<char> steady;
  // per island: steady, its island at rest for kStepsToSleep steps or more, and this is not a
  // check step (a multiple of kSleepCheckSteps)
  std::vector<char> sleeps;
  // per contact of the scene: in one of the step's islands
  std::vector<char> in_step;
  // per body: a contact of it entered or left the step (working storage)
  std::vector<char> touched;
};

/// The sleep plan for the step [state.t, state.t + scene.h] with `islands` (FormIslandsInto's),
/// into `plan` over its last contents. A `state.rest` sized for another scene (or empty) plans
/// every island awake.
void PlanSleep(const Scene& scene, const State& state, const std::vector<Island>& islands,
               SleepPlan& plan);

/// Whether the island's solved step `end` repeats its start in `state` bit for bit: every body's
/// velocities, every contact's ECPs, impulses and σ (its frame aside: a contact with a body turns
/// with that body's round-off) — the step a replay would have taken.
bool RepeatsItsStart(const Island& island, const State& state, const IslandState& end);

/// The island's replay of its last step over `h` seconds: each body's pose advanced by its
/// velocities exactly as every model commits a step (c + h v, IntegrateOrientation), velocities
/// and contacts unchanged.
void ReplayStep(double h, std::vector<BodyState>& bodies);

/// The rest record after the step that `plan` planned was committed into `state`: a body's count
/// grows by one where its island was steady, solved in one step that repeated its start
/// (`island_repeats[i]`, RepeatsItsStart; a replay does) and ended at rest (every body AtRest),
/// else it is 0; its model is the step's (`body_models[b]`, StepReport::models) and its
/// residual island i's (`island_residuals[i]`) where island i was solved, kept where it replayed;
/// each contact's presence in the step is `plan.in_step`.
void RecordRest(const Scene& scene, const std::vector<Island>& islands, const SleepPlan& plan,
                const std::vector<StepModel>& body_models,
                const std::vector<int>& island_substeps, const std::vector<char>& island_repeats,
                const std::vector<double>& island_residuals, State& state);

/// The record of a step taken with sleeping off: which contacts were in it (`plan.in_step`), and
/// no counts, models or residuals, so that it plans every island awake.
void RecordInStepOnly(const SleepPlan& plan, RestRecord& rest);

}  // namespace ecpsim::engine
