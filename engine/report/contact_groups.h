#pragma once
// The contacts of one pair of bodies (or of a body and an obstacle) seen as one: a body made of
// convex parts touches another through a contact per pair of parts (Decomposition::kParts), and
// what a run reports of the pair is their combination, as the multi-patch model combines its
// parts against a plane.

#include <vector>

#include "engine/contact_index.h"
#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// Scene::contacts split into groups (engine/contact_index.h), in order.
std::vector<ContactGroup> ContactGroups(const Scene& scene);

/// The group's contacts combined: a group of one is its contact exactly (warm start dropped).
/// Several: the frame (n, t, o) of the member carrying the largest p_n (the first where none
/// does); p_n, p_t, p_o the members' summed force projected on it; a1, a2 the p_n-weighted means
/// of the members' ECPs (the dominant member's where none carries load); p_r the members' total
/// moment about that a1 along n; σ the p_n-weighted mean of the members' σ.
ContactState CombinedContact(const State& state, const ContactGroup& group);

}  // namespace ecpsim::engine
