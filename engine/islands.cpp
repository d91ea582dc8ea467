#include "engine/islands.h"

#include <algorithm>
#include <array>
#include <numeric>

#include "engine/auto_sides.h"
#include "engine/contact_friction.h"

namespace ecpsim::engine {

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
  in_step.assign(scene.contacts.size(), true);
  // the bounds, computed once and only if a contact needs them
  StepReach& reach = scratch.reach;
  bool reach_known = false;
  const auto known_reach = [&]() -> const StepReach& {
    if (!reach_known) StepReachOf(scene, state, reach);
    reach_known = true;
    return reach;
  };
  // a part of F whose box misses G's is out of reach of each of G's parts, and its contacts
  // with them follow one another: one box test for all of them
  std::array<int, 3> part_checked = {-1, -1, -1};  // body, part, other body
  bool part_reaches = true;
  bool choosing = false;  // whether a pair lists its hulls' and its parts' contacts
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    choosing = choosing || pair.sides != SideChoice::kFixed;
    if (!pair.WithBody()) continue;
    if (pair.part >= 0 && pair.other_part >= 0) {
      const std::array<int, 3> key = {pair.body, pair.part, pair.other_body};
      if (key != part_checked) {
        part_checked = key;
        part_reaches = PartReachesBody(known_reach(), pair);
      }
      if (!part_reaches) {
        in_step[k] = false;
        continue;
      }
    }
    in_step[k] = BodiesInReach(scene, state, known_reach(), static_cast<int>(k));
  }
  // such a pair keeps one of the two within the step (engine/auto_sides.h): those between two
  // bodies before the islands form, so that a set left out joins nothing
  const auto keep_one_set = [&](bool with_body) {
    for (size_t k = 0; choosing && k < scene.contacts.size();) {
      size_t end = k + 1;
      while (end < scene.contacts.size() && scene.contacts[end].SameBodies(scene.contacts[k]))
        ++end;
      const ContactPair& pair = scene.contacts[k];
      if (pair.sides != SideChoice::kFixed && pair.WithBody() == with_body &&
          std::any_of(in_step.begin() + k, in_step.begin() + end, [](char in) { return in; })) {
        const SideChoice dropped = HullsExact(scene, state, known_reach(), static_cast<int>(k))
                                       ? SideChoice::kParts
                                       : SideChoice::kHulls;
        for (size_t j = k; j < end; ++j)
          if (scene.contacts[j].sides == dropped) in_step[j] = false;
      }
      k = end;
    }
  };
  keep_one_set(true);
  // the pairs that join their bodies' islands, and those that stay apart (StaysApart)
  std::vector<int>& apart = scratch.apart;
  apart.clear();
  const bool any_kept = scratch.kept.size() == scene.contacts.size();
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (!in_step[k] || !pair.WithBody() || scene.bodies[pair.other_body].IsKinematic()) continue;
    if (!(any_kept && scratch.kept[k]) &&
        StaysApart(scene, state, known_reach(), static_cast<int>(k))) {
      apart.push_back(static_cast<int>(k));
    } else {
      root[find(pair.body)] = find(pair.other_body);
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
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    if (pair.WithBody() || islands[island_of[find(pair.body)]].bodies.size() < 2) continue;
    in_step[k] = InReach(known_reach().boxes[pair.body], *scene.obstacles[pair.obstacle].shape);
  }
  keep_one_set(false);
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    if (!in_step[k]) continue;
    Island& island = islands[island_of[find(scene.contacts[k].body)]];
    island.contacts.push_back(static_cast<int>(k));
    island.friction.push_back(StepFriction(scene, state, static_cast<int>(k)));
  }
}

std::vector<Island> FormIslands(const Scene& scene, const State& state) {
  std::vector<Island> islands;
  IslandScratch scratch;
  FormIslandsInto(scene, state, scratch, islands);
  return islands;
}

}  // namespace ecpsim::engine
