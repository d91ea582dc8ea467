#include "engine/islands.h"

#include <algorithm>
#include <numeric>

#include "common/errors.h"
#include "engine/auto_sides.h"
#include "engine/contact_friction.h"

namespace ecpsim::engine {
namespace {

// listed pairs of bodies per body above which BodyPairSearch::kAuto sweeps the bodies' boxes
// instead of testing each pair: the sweep costs a sort of the bodies and a test per pair of boxes
// that overlap along x; a scene of stacks in a grid lists 1.5 pairs per body, one of 1,000 bodies
// with every pair 500
constexpr std::size_t kSweepAbovePairsPerBody = 8;

// which contacts of `group` (between two bodies whose boxes meet) are in reach (BodiesInReach),
// into `in_step`: a part of F whose box misses G's box is out of reach of each of G's sides, its
// row skipped at one box test
void TestGroup(const Scene& scene, const State& state, const StepReach& reach,
               const ContactIndex& index, const ContactGroup& group, std::vector<char>& in_step) {
  for (int r = group.rows_begin; r < group.rows_end; ++r) {
    const int begin = index.row_first[r];
    const int end = r + 1 < group.rows_end ? index.row_first[r + 1] : group.end;
    if (scene.contacts[begin].part >= 0 && !PartReachesBody(reach, scene.contacts[begin])) continue;
    for (int k = begin; k < end; ++k) in_step[k] = BodiesInReach(scene, state, reach, k);
  }
}

// The groups whose contacts may be in the step, into scratch.groups in order: each body's with
// obstacles, and those of pairs of bodies whose boxes meet, their contacts tested into `in_step`
// (TestGroup; the obstacles' are set by the caller). Where the scene lists many pairs of bodies (a
// YAML scene's default: every pair) the bodies' boxes are swept and the groups of the pairs found
// looked up; else every group is walked and its two boxes tested. Both give the same groups and
// contacts.
void GroupsInReach(const Scene& scene, const State& state, const ContactIndex& index,
                   const StepReach& reach, IslandScratch& scratch, std::vector<char>& in_step) {
  std::vector<int>& groups = scratch.groups;
  const std::vector<Box>& boxes = reach.boxes;
  // (each group is listed under both its bodies)
  const std::size_t listed = index.body_groups.size() / 2;
  const bool sweep = scratch.search == BodyPairSearch::kAuto
                         ? listed > kSweepAbovePairsPerBody * boxes.size()
                         : scratch.search == BodyPairSearch::kSweep;
  if (!sweep) {
    groups.resize(index.groups.size());
    std::iota(groups.begin(), groups.end(), 0);
    for (const ContactGroup& group : index.groups) {
      const ContactPair& pair = scene.contacts[group.first];
      if (pair.WithBody() && boxes[pair.body].intersects(boxes[pair.other_body]))
        TestGroup(scene, state, reach, index, group, in_step);
    }
    return;
  }
  std::vector<int>& near = scratch.near_groups;
  near.clear();
  OverlappingBoxes(boxes, scratch.sweep, scratch.box_pairs);
  for (const auto& [a, b] : scratch.box_pairs) {
    const auto [first, last] = index.GroupsBetween(a, b);
    for (const auto* it = first; it != last; ++it) {
      // (an index of other contacts than the scene's: they changed after IndexContacts)
      const ContactPair& pair = scene.contacts[index.groups[it->second].first];
      ECPSIM_DEMAND(std::minmax(pair.body, pair.other_body) == std::minmax(a, b));
      near.push_back(it->second);
      TestGroup(scene, state, reach, index, index.groups[it->second], in_step);
    }
  }
  // in the order of their contacts, which the islands list in order
  std::sort(near.begin(), near.end());
  groups.resize(near.size() + index.obstacle_groups.size());
  std::merge(near.begin(), near.end(), index.obstacle_groups.begin(), index.obstacle_groups.end(),
             groups.begin());
}

}  // namespace

void FormIslandsInto(const Scene& scene, const State& state, IslandScratch& scratch,
                     std::vector<Island>& islands) {
  const int n = static_cast<int>(scene.bodies.size());
  // union–find over the dynamic bodies joined by a contact in the step
  std::vector<int>& root = scratch.root;
  root.resize(n);
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int b) {
    while (root[b] != b) b = root[b] = root[root[b]];
    return b;
  };
  std::vector<char>& in_step = scratch.in_step;
  in_step.assign(scene.contacts.size(), false);
  const ContactIndex& index = ContactIndexOf(scene, scratch.index);
  // the bounds, computed once and only if a contact needs them
  StepReach& reach = scratch.reach;
  bool reach_known = false;
  const auto known_reach = [&]() -> const StepReach& {
    if (!reach_known) StepReachOf(scene, state, reach);
    reach_known = true;
    return reach;
  };
  // the contacts that may be in the step, by their groups: every body's with obstacles, and
  // those of bodies that can touch
  for (const int g : index.obstacle_groups) {
    ECPSIM_DEMAND(!scene.contacts[index.groups[g].first].WithBody());
    std::fill(in_step.begin() + index.groups[g].first, in_step.begin() + index.groups[g].end, true);
  }
  const std::vector<int>& groups = scratch.groups;
  if (index.body_groups.empty()) {
    scratch.groups = index.obstacle_groups;
  } else {
    GroupsInReach(scene, state, index, known_reach(), scratch, in_step);
  }
  // such a pair keeps one of the two within the step (engine/auto_sides.h): those between two
  // bodies before the islands form, so that a set left out joins nothing
  const auto keep_one_set = [&](bool with_body) {
    if (!index.chooses_sides) return;
    for (const int g : groups) {
      const ContactGroup& group = index.groups[g];
      const ContactPair& pair = scene.contacts[group.first];
      if (pair.sides != SideChoice::kFixed && pair.WithBody() == with_body &&
          std::any_of(in_step.begin() + group.first, in_step.begin() + group.end,
                      [](char in) { return in; })) {
        const SideChoice dropped = HullsExact(scene, state, known_reach(), group.first)
                                       ? SideChoice::kParts
                                       : SideChoice::kHulls;
        for (int k = group.first; k < group.end; ++k)
          if (scene.contacts[k].sides == dropped) in_step[k] = false;
      }
    }
  };
  keep_one_set(true);
  // the pairs that join their bodies' islands, and those that stay apart (StaysApart)
  std::vector<int>& apart = scratch.apart;
  apart.clear();
  const bool any_kept = scratch.kept.size() == scene.contacts.size();
  for (const int g : groups) {
    for (int k = index.groups[g].first; k < index.groups[g].end; ++k) {
      const ContactPair& pair = scene.contacts[k];
      if (!in_step[k] || !pair.WithBody() || scene.bodies[pair.other_body].IsKinematic()) continue;
      if (!(any_kept && scratch.kept[k]) && StaysApart(scene, state, known_reach(), k)) {
        apart.push_back(k);
      } else {
        root[find(pair.body)] = find(pair.other_body);
      }
    }
  }
  // a gripper's jaws move as one (island_gripper.h)
  for (const Gripper& gripper : scene.grippers) root[find(gripper.jaws[0])] = find(gripper.jaws[1]);
  // a pair that stays apart between two islands is left out of the step (the driver verifies
  // that it ends apart); within one island it stays in, as a block of the island's MNCP
  apart.erase(std::remove_if(apart.begin(), apart.end(),
                             [&](int k) {
                               const ContactPair& pair = scene.contacts[k];
                               return find(pair.body) == find(pair.other_body);
                             }),
              apart.end());
  for (int k : apart) in_step[k] = false;
  std::vector<int>& island_of = scratch.island_of;
  island_of.assign(n, -1);
  size_t count = 0;
  for (int b = 0; b < n; ++b) {
    if (scene.bodies[b].IsKinematic()) continue;
    const int r = find(b);
    if (island_of[r] < 0) {
      island_of[r] = static_cast<int>(count);
      if (count == islands.size()) islands.emplace_back();
      islands[count].bodies.clear();
      islands[count].contacts.clear();
      islands[count].friction.clear();
      ++count;
    }
    islands[island_of[r]].bodies.push_back(b);
  }
  islands.resize(count);
  // an obstacle out of reach of a body of a coupled island leaves its MNCP: there every contact
  // is a block of the coupled Newton system (the stack's upper boxes over the ground, a gripper's
  // jaws over the table), while a body alone takes far obstacles in closed form (free flight)
  for (const int g : index.obstacle_groups) {
    for (int k = index.groups[g].first; k < index.groups[g].end; ++k) {
      const ContactPair& pair = scene.contacts[k];
      if (islands[island_of[find(pair.body)]].bodies.size() < 2) continue;
      in_step[k] = InReach(known_reach().boxes[pair.body], *scene.obstacles[pair.obstacle].shape);
    }
  }
  keep_one_set(false);
  for (const int g : groups) {
    for (int k = index.groups[g].first; k < index.groups[g].end; ++k) {
      if (!in_step[k]) continue;
      Island& island = islands[island_of[find(scene.contacts[k].body)]];
      island.contacts.push_back(k);
      island.friction.push_back(StepFriction(scene, state, k));
    }
  }
}

std::vector<Island> FormIslands(const Scene& scene, const State& state) {
  std::vector<Island> islands;
  IslandScratch scratch;
  FormIslandsInto(scene, state, scratch, islands);
  return islands;
}

}  // namespace ecpsim::engine
