// The broad phase (engine/broad_phase.h): which pairs of bodies a step solves — those that can
// touch within it, whatever the world axes.

#include "engine/broad_phase.h"

#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "engine/islands.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

constexpr double kBoxSize = 0.1;  // m: scenes/pyramid.yaml's cubes

// six cubes in a pile 3-2-1 in the x–z plane, each on the two below, the bottom ones touching
// side by side (scenes/pyramid.yaml's kind), turned about z by `yaw` (rad) as a whole; every pair
// of bodies a contact pair
Scene TurnedPile(double yaw) {
  const Eigen::AngleAxisd turn(yaw, Vector3d::UnitZ());
  const std::vector<Vector3d> centres = {{-0.1, 0, 0.05},  {0, 0, 0.05},    {0.1, 0, 0.05},
                                         {-0.05, 0, 0.15}, {0.05, 0, 0.15}, {0, 0, 0.25}};
  std::vector<Body> boxes;
  for (size_t i = 0; i < centres.size(); ++i) {
    Body box = testing::MakeBoxBody(Vector3d::Constant(kBoxSize), 1, "b" + std::to_string(i));
    box.p0 = turn * centres[i];
    box.q0 = Eigen::Quaterniond(turn);
    boxes.push_back(box);
  }
  Scene scene = testing::MakeGroundScene(std::move(boxes));
  AddBodyPairs(scene);
  return scene;
}

// The pairs of bodies (lower index first) the broad phase finds in reach: whose contact is in
// one of the step's islands (`in_islands`) or left out of them as staying apart (`apart`)
struct PairsInReach {
  std::set<std::pair<int, int>> in_islands, apart;
  std::set<std::pair<int, int>> All() const {
    std::set<std::pair<int, int>> all = in_islands;
    all.insert(apart.begin(), apart.end());
    return all;
  }
};

PairsInReach BodyPairsInReach(const Scene& scene, const State& state) {
  IslandScratch scratch;
  std::vector<Island> islands;
  FormIslandsInto(scene, state, scratch, islands);
  PairsInReach pairs;
  const auto bodies_of = [&](int k) {
    return std::make_pair(scene.contacts[k].body, scene.contacts[k].other_body);
  };
  for (const Island& island : islands) {
    for (int k : island.contacts)
      if (scene.contacts[k].WithBody()) pairs.in_islands.insert(bodies_of(k));
  }
  for (int k : scratch.apart) pairs.apart.insert(bodies_of(k));
  return pairs;
}

TEST(BroadPhaseTest, APileTurnedAboutZSolvesTheSamePairsOfBodies) {
  const std::set<std::pair<int, int>> touching = {{0, 1}, {1, 2}, {0, 3}, {1, 3}, {1, 4},
                                                  {2, 4}, {3, 4}, {3, 5}, {4, 5}};
  for (const double degrees : {0.0, 37.0, 90.0}) {
    const Scene scene = TurnedPile(degrees * M_PI / 180);
    // the bottom corner box and the box above its far neighbour are 5 cm apart, although at 37°
    // their world boxes overlap
    EXPECT_EQ(BodyPairsInReach(scene, InitialState(scene)).All(), touching) << degrees << "°";
  }
}

TEST(BroadPhaseTest, APairApartByMoreThanItsReachIsOutOfTheStepUntilItCanTouch) {
  // two cubes 5 cm apart along x, 0.5 m above the ground, turned by 37° about z together;
  // h = 0.01 s
  const Eigen::AngleAxisd turn(37 * M_PI / 180, Vector3d::UnitZ());
  std::vector<Body> boxes;
  for (const int i : {0, 1}) {
    Body box = testing::MakeBoxBody(Vector3d::Constant(kBoxSize), 1, "b" + std::to_string(i));
    box.p0 = turn * Vector3d(i * (kBoxSize + 0.05), 0, 0.5);
    box.q0 = Eigen::Quaterniond(turn);
    boxes.push_back(box);
  }
  Scene scene = testing::MakeGroundScene(std::move(boxes));
  AddBodyPairs(scene);
  State state = InitialState(scene);
  EXPECT_TRUE(BodyPairsInReach(scene, state).All().empty()) << "at rest";
  // each body reaches h (|v| + h |g| + V_max) in the step, V_max the fastest body's speed (what a
  // struck body can get): with the first at v, together h (3 v + 4 h |g|), in any direction
  const auto moving = [&](double speed) {
    state.bodies[0].v_WB = turn * Vector3d(-speed, 0, 0);
    return BodyPairsInReach(scene, state).All();
  };
  EXPECT_TRUE(moving(1).empty()) << "3.4 cm";
  EXPECT_EQ(moving(2), (std::set<std::pair<int, int>>{{0, 1}})) << "6.4 cm";
}

TEST(BroadPhaseTest, APairInReachThatItsOwnMotionsCannotCloseStaysOutOfTheIslands) {
  // two cubes 5 cm apart along x on the ground, turned by 37° about z; h = 0.01 s. The first
  // moves toward the second at v: by its own motion and gravity it can close h (v + 2 h |g|) of
  // the gap (the second, at rest, h² |g|)
  const Eigen::AngleAxisd turn(37 * M_PI / 180, Vector3d::UnitZ());
  std::vector<Body> boxes;
  for (const int i : {0, 1}) {
    Body box = testing::MakeBoxBody(Vector3d::Constant(kBoxSize), 1, "b" + std::to_string(i));
    box.p0 = turn * Vector3d(i * (kBoxSize + 0.05), 0, kBoxSize / 2);
    box.q0 = Eigen::Quaterniond(turn);
    boxes.push_back(box);
  }
  Scene scene = testing::MakeGroundScene(std::move(boxes));
  AddBodyPairs(scene);
  State state = InitialState(scene);
  const auto approaching = [&](double speed) {
    state.bodies[0].v_WB = turn * Vector3d(speed, 0, 0);
    return BodyPairsInReach(scene, state);
  };
  const std::set<std::pair<int, int>> pair = {{0, 1}};
  // 2.2 cm of own motion: in reach (6.4 cm), left out as staying apart
  const PairsInReach slow = approaching(2);
  EXPECT_TRUE(slow.in_islands.empty());
  EXPECT_EQ(slow.apart, pair);
  // 6.2 cm: it may touch within the step, so the two share an island
  const PairsInReach fast = approaching(6);
  EXPECT_EQ(fast.in_islands, pair);
  EXPECT_TRUE(fast.apart.empty());
  // a pair that carried a load over the last step is never left out
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    if (scene.contacts[k].WithBody()) state.contacts[k].p_n = 1e-3;
  EXPECT_EQ(approaching(2).in_islands, pair);
}

TEST(BroadPhaseTest, APairThatStaysApartWithinOneIslandStaysInIt) {
  // three cubes touching in a row along x on the ground, the first moving along the row at
  // 6 m/s: the first and the third, 10 cm apart, are in reach (12 cm) and stay apart by their
  // own motions (6 cm), but the middle one joins them into one island, whose MNCP keeps their
  // pair as a block
  std::vector<Body> boxes;
  for (const int i : {0, 1, 2}) {
    Body box = testing::MakeBoxBody(Vector3d::Constant(kBoxSize), 1, "b" + std::to_string(i));
    box.p0 = Vector3d(i * kBoxSize, 0, kBoxSize / 2);
    boxes.push_back(box);
  }
  boxes[0].v0 = Vector3d(6, 0, 0);
  Scene scene = testing::MakeGroundScene(std::move(boxes));
  AddBodyPairs(scene);
  const PairsInReach pairs = BodyPairsInReach(scene, InitialState(scene));
  EXPECT_EQ(pairs.in_islands, (std::set<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 2}}));
  EXPECT_TRUE(pairs.apart.empty());
}

}  // namespace
}  // namespace ecpsim::engine
