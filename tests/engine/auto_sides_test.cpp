// decomposition: auto (engine/auto_sides.h): a pair takes its hulls' one contact where nothing can
// reach into a cavity, and its parts' contacts where something can — scenes/cube_in_cup.yaml's
// cup under auto, against the same cup under `none` and `parts`.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/auto_sides.h"
#include "engine/broad_phase.h"
#include "engine/report/penetration.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// m: where a body rests on a part, as in part_contacts_test.cpp (the gap rows' convergence in
// the contact's length plus the coordinates' round-off)
constexpr double kRestTolerance = 1e-9;

Scene Cup(const std::string& decomposition, std::vector<std::string> overrides = {}) {
  overrides.push_back("bodies.0.decomposition=" + decomposition);
  return LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/cube_in_cup.yaml", overrides).scene;
}

// the first contact of the cup–cube pair's hulls' set
int HullsContact(const Scene& scene) {
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    if (scene.contacts[k].sides == SideChoice::kHulls && scene.contacts[k].WithBody())
      return static_cast<int>(k);
  return -1;
}

// the cube's and the cup's poses over a run, and each step's model of the cup
struct CupRun {
  std::vector<Eigen::Vector3d> cube, cup;
  std::vector<StepModel> cup_models;
};

CupRun RunOf(const Scene& scene) {
  CupRun run;
  State state = InitialState(scene);
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  for (int k = 0; k < steps; ++k) {
    const StepReport report = Step(scene, state);
    EXPECT_TRUE(report.converged) << "t = " << state.t;
    run.cube.push_back(state.bodies[1].p_WB);
    run.cup.push_back(state.bodies[0].p_WB);
    run.cup_models.push_back(report.models[0]);
  }
  return run;
}

double LargestDifference(const CupRun& a, const CupRun& b) {
  double largest = 0;
  for (size_t k = 0; k < a.cube.size(); ++k) {
    largest = std::max({largest, (a.cube[k] - b.cube[k]).norm(), (a.cup[k] - b.cup[k]).norm()});
  }
  return largest;
}

TEST(AutoSidesTest, ThePairListsTheHullsContactThenThePartsContacts) {
  const Scene scene = Cup("auto");
  ASSERT_EQ(scene.bodies[0].decomposition, Decomposition::kAuto);
  EXPECT_EQ(scene.bodies[0].lids.size(), 1u);  // the cup's opening
  std::vector<ContactPair> pair;
  for (const ContactPair& c : scene.contacts)
    if (c.WithBody()) pair.push_back(c);
  ASSERT_EQ(pair.size(), 6u);  // the hulls, then each of the cup's 5 parts against the cube
  EXPECT_EQ(pair[0].sides, SideChoice::kHulls);
  EXPECT_EQ(pair[0].part, -1);
  for (size_t i = 1; i < pair.size(); ++i) {
    EXPECT_EQ(pair[i].sides, SideChoice::kParts);
    EXPECT_EQ(pair[i].part, static_cast<int>(i) - 1);
  }
}

TEST(AutoSidesTest, ACubeStrikingTheCupsOuterWallTakesTheHullsOneContact) {
  // the cube slides on the table into the cup's +x wall, a face of the hull the cup's parts
  // cover: the run is the one of the cup's hull, to the bit
  const std::vector<std::string> slide = {"bodies.1.position=[0.075, 0, 0.02]",
                                          "bodies.1.rpy=[0, 0, 0]",
                                          "bodies.1.velocity=[-0.3, 0, 0]", "duration=0.3"};
  const CupRun with_auto = RunOf(Cup("auto", slide));
  const CupRun with_hull = RunOf(Cup("none", slide));
  EXPECT_EQ(LargestDifference(with_auto, with_hull), 0);
  // it reached the wall (its face at 0.05 m, the cube's half edge 0.02 m) and pushed the cup
  EXPECT_NEAR(with_auto.cube.back().x(), 0.07, 1e-8);
  EXPECT_LT(with_auto.cup.back().x(), 0);
  for (StepModel model : with_auto.cup_models) EXPECT_NE(model, StepModel::kParts);
}

TEST(AutoSidesTest, ACubeDroppedIntoTheCupTakesThePartsNearTheOpening) {
  const Scene scene = Cup("auto");
  const int k = HullsContact(scene);
  State state = InitialState(scene);
  StepReach reach;
  // at the start the cube's lowest point is ≥ 0.12 − 0.0347 m (its half diagonal), 5 mm above
  // the opening's plane (the cup's top, 0.08 m) and beyond the step's reach: the hulls' contact
  // is exact; once its centre is below 0.10 m, its lowest point (≥ its half edge, 0.02 m, below
  // the centre) is in the opening: it is not
  StepReachOf(scene, state, reach);
  EXPECT_TRUE(HullsExact(scene, state, reach, k));
  int below = 0;
  for (int step = 0; step < 40; ++step) {
    ASSERT_TRUE(Step(scene, state).converged);
    StepReachOf(scene, state, reach);
    if (state.bodies[1].p_WB.z() >= 0.10) continue;
    EXPECT_FALSE(HullsExact(scene, state, reach, k)) << "t = " << state.t;
    ++below;
  }
  EXPECT_GT(below, 0);
  // and it comes to rest on the floor as with the parts alone, to the bit
  const CupRun with_auto = RunOf(scene);
  const CupRun with_parts = RunOf(Cup("parts"));
  EXPECT_NEAR(with_auto.cube.back().z(), 0.03, kRestTolerance);
  // (the hulls' contact, out of touch while it is kept, joins no island)
  EXPECT_EQ(LargestDifference(with_auto, with_parts), 0);
  EXPECT_EQ(with_auto.cup_models.back(), StepModel::kParts);
}

TEST(AutoSidesTest, ACubeInsideTheCupFarBelowTheOpeningTakesTheParts) {
  // on the floor from the start: 3 cm below the opening, out of reach of the lid; inside the hull
  const Scene scene = Cup("auto", {"bodies.1.position=[0, 0, 0.03]", "bodies.1.rpy=[0, 0, 0]"});
  const State state = InitialState(scene);
  StepReach reach;
  StepReachOf(scene, state, reach);
  EXPECT_FALSE(HullsExact(scene, state, reach, HullsContact(scene)));
  const CupRun run = RunOf(scene);
  EXPECT_NEAR(run.cube.back().z(), 0.03, kRestTolerance);
  for (StepModel model : run.cup_models) EXPECT_EQ(model, StepModel::kParts);
}

// a kinematic 2 cm cube, the cube's body replaced, starting at `position` and moving at `velocity`
std::string KinematicFinger(const std::string& position, const std::string& velocity) {
  return "bodies.1={name: finger, kinematic: true, shape: {box: {size: [0.02, 0.02, 0.02]}}, "
         "motion: {velocity: {position: " +
         position + ", linear: " + velocity + "}}}";
}

TEST(AutoSidesTest, AKinematicFingerPushingTheOuterWallTakesTheHullsOneContact) {
  // its box (which holds its motion) meets no lid: the cup moves as against its hull, to the bit
  const std::vector<std::string> push = {KinematicFinger("[0.07, 0, 0.04]", "[-0.05, 0, 0]"),
                                         "duration=0.5"};
  const CupRun with_auto = RunOf(Cup("auto", push));
  const CupRun with_hull = RunOf(Cup("none", push));
  EXPECT_EQ(LargestDifference(with_auto, with_hull), 0);
  EXPECT_LT(with_auto.cup.back().x(), -0.01);  // pushed 1–1.5 cm (the wall met at 0.2 s)
  for (StepModel model : with_auto.cup_models) EXPECT_NE(model, StepModel::kParts);
}

TEST(AutoSidesTest, AKinematicFingerEnteringTheOpeningTakesTheParts) {
  // coming down over the opening: exact while its box misses the lid's, not from the step it
  // meets it (the finger's bottom within its step's travel of the rim plane, 0.08 m)
  const Scene scene = Cup("auto", {KinematicFinger("[0, 0, 0.1]", "[0, 0, -0.05]")});
  const int k = HullsContact(scene);
  State state = InitialState(scene);
  StepReach reach;
  StepReachOf(scene, state, reach);
  EXPECT_TRUE(HullsExact(scene, state, reach, k));
  while (state.bodies[1].p_WB.z() - 0.01 > 0.08) {
    ASSERT_TRUE(Step(scene, state).converged);
    StepReachOf(scene, state, reach);
  }
  EXPECT_FALSE(HullsExact(scene, state, reach, k));
}

TEST(AutoSidesTest, AKinematicBodyOfPartsAlwaysMeetsThem) {
  // a kinematic cup under auto: its lids move within the step, its reach is its swept box
  const Scene scene = Cup(
      "auto", {"bodies.0={name: cup, mesh: meshes/cup.obj, kinematic: true, decomposition: auto, "
               "motion: {velocity: {position: [0, 0, 0.04], linear: [0, 0, 0]}}, parts: ["
               "{box: {size: [0.10, 0.10, 0.01]}, at: [0, 0, 0.005]}, "
               "{box: {size: [0.01, 0.10, 0.075]}, at: [-0.045, 0, 0.0425]}, "
               "{box: {size: [0.01, 0.10, 0.075]}, at: [0.045, 0, 0.0425]}, "
               "{box: {size: [0.09, 0.01, 0.075]}, at: [0, -0.045, 0.0425]}, "
               "{box: {size: [0.09, 0.01, 0.075]}, at: [0, 0.045, 0.0425]}]}",
               "bodies.1.position=[0.3, 0, 0.2]"});
  ASSERT_EQ(scene.bodies[0].decomposition, Decomposition::kAuto);
  const State state = InitialState(scene);
  StepReach reach;
  StepReachOf(scene, state, reach);
  EXPECT_FALSE(HullsExact(scene, state, reach, HullsContact(scene)));
}

}  // namespace
}  // namespace ecpsim::engine
