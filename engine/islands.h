#pragma once
// Contact islands: the dynamic bodies that contacts in the step join, each group solved as one
// MNCP (engine/README.md, "Islands").

#include <utility>
#include <vector>

#include "engine/broad_phase.h"
#include "engine/contact_index.h"
#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// How FormIslandsInto finds the pairs of bodies whose boxes meet: they give the same pairs, at
/// different costs.
enum class BodyPairSearch {
  kAuto,    // kSweep where the scene lists more than 8 pairs of bodies per body, else kListed
  kSweep,   // sweep and prune over every body's box (OverlappingBoxes)
  kListed,  // each pair of bodies the scene lists contacts of, its two boxes tested
};

/// FormIslandsInto's working storage, kept by the caller from step to step so that a step in a
/// steady state allocates nothing.
struct IslandScratch {
  std::vector<int> root, island_of;  // the union–find's roots, each root's island
  std::vector<char> in_step;         // each contact's presence in the step
  StepReach reach;                   // the broad phase's bounds, where a contact needs them
  ContactIndex index;                // the scene's, where it has none (Scene::contact_index)
  BoxSweep sweep;                    // the box sweep's working storage (OverlappingBoxes)
  std::vector<std::pair<int, int>> box_pairs;  // the bodies whose boxes meet
  std::vector<int> near_groups;                // the groups of bodies whose boxes meet
  std::vector<int> groups;  // the contact groups that may be in the step, in order
  /// contacts left out of the step as staying apart between two islands, for the driver to verify
  std::vector<int> apart;
  /// per contact: kept in the step whatever StaysApart says (the driver found it not apart at
  /// the step's end); empty or sized as the scene's contacts, set by the caller
  std::vector<char> kept;
  BodyPairSearch search = BodyPairSearch::kAuto;  // set by the caller to compare the two
};

/// The scene's islands for the step [t, t + h] from `state` (in order of their lowest body):
/// the broad phase bounds each body by a world box holding its hull and everything it can reach
/// within the step (its own speed, spin, loads and gravity over h, plus what the fastest body of
/// the scene can give it); a kinematic body's box holds its hull at the step's two ends. A
/// contact between two bodies is in the step (two dynamic bodies then share an island) where
/// they can touch within it (BodiesInReach: their boxes overlap and, but for a kinematic body,
/// their hulls lie within what the two can move); otherwise they cannot touch in the step. Every
/// dynamic body is in exactly one island, with all its contacts with obstacles; kinematic bodies
/// are in none (their motion is given). Of a pair that lists its hulls' and its parts' contacts
/// (Decomposition::kAuto) only one set is in the step, and only it joins the bodies' islands:
/// the hulls' where HullsExact says so (engine/auto_sides.h), else the parts'. A contact between
/// two bodies that stays apart unless the step's contacts push them (StaysApart), and whose
/// bodies the other contacts leave in two islands, joins nothing: it is listed in `apart`
/// instead, unless `kept` names it. Each contact's friction is StepFriction's at `state`.
std::vector<Island> FormIslands(const Scene& scene, const State& state);

/// FormIslands into `islands`, over their last contents (reusing their storage).
void FormIslandsInto(const Scene& scene, const State& state, IslandScratch& scratch,
                     std::vector<Island>& islands);

}  // namespace ecpsim::engine
