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

// the pairs of bodies (lower index first) whose contact is in one of the step's islands
std::set<std::pair<int, int>> BodyPairsInStep(const Scene& scene, const State& state) {
  std::set<std::pair<int, int>> pairs;
  for (const Island& island : FormIslands(scene, state)) {
    for (int k : island.contacts) {
      const ContactPair& pair = scene.contacts[k];
      if (pair.WithBody()) pairs.emplace(pair.body, pair.other_body);
    }
  }
  return pairs;
}

TEST(BroadPhaseTest, APileTurnedAboutZSolvesTheSamePairsOfBodies) {
  const std::set<std::pair<int, int>> touching = {{0, 1}, {1, 2}, {0, 3}, {1, 3}, {1, 4},
                                                  {2, 4}, {3, 4}, {3, 5}, {4, 5}};
  for (const double degrees : {0.0, 37.0, 90.0}) {
    const Scene scene = TurnedPile(degrees * M_PI / 180);
    // the bottom corner box and the box above its far neighbour are 5 cm apart, although at 37°
    // their world boxes overlap
    EXPECT_EQ(BodyPairsInStep(scene, InitialState(scene)), touching) << degrees << "°";
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
  EXPECT_TRUE(BodyPairsInStep(scene, state).empty()) << "at rest";
  // each body reaches h (|v| + h |g| + V_max) in the step, V_max the fastest body's speed (what a
  // struck body can get): with the first at v, together h (3 v + 4 h |g|), in any direction
  const auto moving = [&](double speed) {
    state.bodies[0].v_WB = turn * Vector3d(-speed, 0, 0);
    return BodyPairsInStep(scene, state);
  };
  EXPECT_TRUE(moving(1).empty()) << "3.4 cm";
  EXPECT_EQ(moving(2), (std::set<std::pair<int, int>>{{0, 1}})) << "6.4 cm";
}

}  // namespace
}  // namespace ecpsim::engine
