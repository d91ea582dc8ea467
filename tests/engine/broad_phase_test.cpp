// The broad phase (engine/broad_phase.h): which pairs of bodies a step solves — those that can
// touch within it, whatever the world axes.

#include "engine/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "engine/islands.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"
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

// the islands (bodies, contacts and their friction) and the pairs left out as apart
void ExpectSameIslands(const Scene& scene, const State& state) {
  IslandScratch swept, listed;
  swept.search = BodyPairSearch::kSweep;
  listed.search = BodyPairSearch::kListed;
  std::vector<Island> a, b;
  FormIslandsInto(scene, state, swept, a);
  FormIslandsInto(scene, state, listed, b);
  ASSERT_EQ(a.size(), b.size()) << "t = " << state.t;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].bodies, b[i].bodies) << "t = " << state.t;
    EXPECT_EQ(a[i].contacts, b[i].contacts) << "t = " << state.t;
    ASSERT_EQ(a[i].friction.size(), b[i].friction.size());
    for (size_t k = 0; k < a[i].friction.size(); ++k)
      EXPECT_EQ(a[i].friction[k].e_r, b[i].friction[k].e_r);
  }
  EXPECT_EQ(swept.apart, listed.apart) << "t = " << state.t;
}

TEST(BroadPhaseTest, TheBoxSweepAndTheListedPairsFormTheSameIslandsEveryStep) {
  // a pile falling (the dominoes' cascade, 9 bodies), a cube falling into a mug of parts
  for (const char* name : {"dominoes.yaml", "cube_in_mug.yaml"}) {
    SCOPED_TRACE(name);
    const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + name).scene;
    State state = InitialState(scene);
    // 0.5 s at h = 0.005 s: the dominoes' landings, the cube's fall into the mug and its rest
    constexpr int kSteps = 100;
    for (int k = 0; k < kSteps; ++k) {
      ExpectSameIslands(scene, state);
      ASSERT_TRUE(Step(scene, state).converged);
    }
  }
  ExpectSameIslands(TurnedPile(37 * M_PI / 180), InitialState(TurnedPile(37 * M_PI / 180)));
}

// the sweep against every pair tested: boxes of many sizes (touching ones among them, whose
// faces meet exactly), one reaching everything (an overflowed bound) and one with a NaN bound
TEST(BroadPhaseTest, TheBoxSweepFindsEveryPairOfBoxesThatMeetAndNoOther) {
  std::vector<Box> boxes;
  unsigned seed = 12345;
  const auto uniform = [&]() {
    seed = seed * 1103515245u + 12345u;
    return static_cast<double>((seed >> 8) % 10000) / 10000.0;
  };
  for (int i = 0; i < 200; ++i) {
    const Vector3d low(uniform(), uniform(), uniform());
    const Vector3d size = Vector3d(uniform(), uniform(), uniform()) * (i % 7 == 0 ? 0.5 : 0.05);
    boxes.emplace_back(low, low + size);
  }
  // a box whose lower x face is another's upper one: they meet (Box::intersects holds bounds)
  boxes.emplace_back(Vector3d(boxes[3].max().x(), boxes[3].min().y(), boxes[3].min().z()),
                     Vector3d(boxes[3].max().x() + 0.1, boxes[3].max().y(), boxes[3].max().z()));
  boxes.emplace_back(Vector3d::Constant(-INFINITY), Vector3d::Constant(INFINITY));
  boxes.emplace_back(Vector3d(NAN, 0, 0), Vector3d(1, 1, 1));
  std::vector<std::pair<int, int>> expected;
  for (size_t i = 0; i < boxes.size(); ++i) {
    for (size_t j = i + 1; j < boxes.size(); ++j) {
      if (boxes[i].intersects(boxes[j])) expected.emplace_back(i, j);
    }
  }
  BoxSweep sweep;
  std::vector<std::pair<int, int>> pairs;
  OverlappingBoxes(boxes, sweep, pairs);
  std::sort(pairs.begin(), pairs.end());
  EXPECT_EQ(pairs, expected);
  EXPECT_TRUE(std::find(pairs.begin(), pairs.end(), std::make_pair(3, 200)) != pairs.end());
  // the infinite box meets every box but the one with a NaN bound
  EXPECT_EQ(std::count_if(pairs.begin(), pairs.end(),
                          [](const auto& p) { return p.first == 201 || p.second == 201; }),
            201);
  // and the list is rebuilt, not appended to, on the next call
  OverlappingBoxes(boxes, sweep, pairs);
  std::sort(pairs.begin(), pairs.end());
  EXPECT_EQ(pairs, expected);
}

}  // namespace
}  // namespace ecpsim::engine
