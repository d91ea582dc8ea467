// A shipped multi-body scene turned about the vertical moves the same way, turned: the scene
// and its copy turned by 90° and by 37° (tests/engine/turned_scene.h) stepped side by side over
// the scene's whole duration, the copy's poses turned back (tests/engine/turned_deviation.h).
// `build/tests/ecpsim_rotation_check scenes` prints the same measurement for every such scene.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/scene_io/scene_yaml.h"
#include "tests/engine/turned_deviation.h"

namespace ecpsim::engine {
namespace {

// m: the criterion for every shipped multi-body scene turned about z, on the CMs and on
// the bodies' surfaces (the orientation's difference × the body's radius); the bodies are
// 0.1–0.3 m, so it is 1e-5 of the smallest. Today's deviations of the scenes asserted here are
// round-off (ecpsim_rotation_check: ≤ 8.4e-12 m)
constexpr double kTurnedMotionTolerance = 1e-6;

// the turns: a quarter turn (the coordinates permuted exactly) and one that aligns no
// face with a world axis and rounds every product
const double kTurns[] = {M_PI / 2, 37 * M_PI / 180};

// the shipped multi-body scenes that meet the criterion today, asserted below
const std::vector<std::string> kAsserted = {
    "cube_in_cup.yaml", "cube_in_mug.yaml", "cube_on_dumbbell.yaml",
    "peg_in_hole.yaml", "push_box.yaml",    "pyramid.yaml",
    "stack.yaml",       "train.yaml"};
// those that do not yet under the default selection: their steps' solutions form sets
// (non-isolated solutions) where the sticking creep's root depends on the Newton path
// (engine/README.md, "Non-isolated solutions: the minimum-norm pass"); the least-energy
// selection, asserted below for the first and the last, picks one point of the set whatever the
// frame. The hook's mug pivots on its far edge on the table while the hook's tip lifts it along a
// line across its handle's arm (ecpsim_rotation_check: 1.2e-3 m at 90°, 9.8e-4 m at 37°, at
// 0.5–0.9 s); under the least-energy selection it takes 9.5 min of CPU for its 3 s. The
// dominoes' first landing, d1 on d2 at 0.34 s, has two roots 2.2e-3 m/s apart, and which one
// Newton reaches depends on the frame's round-off: turned by 0.3, 1.0, 2.0 and π rad their
// copies missed by 2.9e-5 … 3.3e-4 m before the warm start carried its points (they met it at
// 90°, 37° and 2.5 rad, where both frames' paths reached the same root), and by 1.5e-5 …
// 3.2e-4 m at those seven turns since; their cascade up to that landing is asserted below
const std::vector<std::string> kNotYet = {"dominoes.yaml", "gripper.yaml", "hook.yaml",
                                          "tbar_push.yaml"};

void ExpectTurnedMotion(const std::string& name, const std::vector<std::string>& overrides = {}) {
  const Scene scene =
      LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + name, overrides).scene;
  const int steps = testing::RotationCheckSteps(scene);
  for (const double angle : kTurns) {
    testing::TurnedDeviation d;
    // a SolverFailure of either run fails the test with its message
    EXPECT_NO_THROW(d = testing::MeasureTurnedDeviation(scene, angle, steps))
        << name << ", turned by " << angle;
    std::printf("%s turned by %.6g rad: CM %.3g m (%s at %.2f s), angle %.3g rad, over %d steps\n",
                name.c_str(), angle, d.position, d.body.c_str(), d.time, d.angle, d.steps);
    EXPECT_EQ(d.steps, steps) << name;
    EXPECT_LE(d.position, kTurnedMotionTolerance) << name << ", turned by " << angle;
    EXPECT_LE(d.surface, kTurnedMotionTolerance) << name << ", turned by " << angle;
  }
}

TEST(RotationInvarianceTest, StackRestsTheSameWayTurned) {
  // three boxes at rest 10 s, each on a whole face of the one below
  ExpectTurnedMotion("stack.yaml");
}

TEST(RotationInvarianceTest, PushBoxMovesTheSameWayTurned) {
  // a pusher at constant velocity pushes a box through its CM for 2 s
  ExpectTurnedMotion("push_box.yaml");
}

TEST(RotationInvarianceTest, TrainMovesTheSameWayTurned) {
  // a pusher at constant velocity pushes a row of six boxes for 2 s (ecpsim_rotation_check:
  // 2.6e-14 m at 90°, 1.2e-14 m at 37°); most of its CPU is the first step of each run, the
  // strike
  ExpectTurnedMotion("train.yaml");
}

TEST(RotationInvarianceTest, PyramidRestsTheSameWayTurned) {
  // ten boxes 4-3-2-1, each on two below, at rest for 2 s (ecpsim_rotation_check: 4e-15 m at
  // both turns); turned by 37° its first step failed while the broad phase took in pairs 5 cm
  // apart whose world boxes the turn made overlap (engine/README.md, "Broad phase and islands")
  ExpectTurnedMotion("pyramid.yaml");
}

TEST(RotationInvarianceTest, DominoesToppleTheSameWayTurnedUntilTheFirstLanding) {
  // nine blocks, the first pushed over onto the next, until just before it lands on it (0.33
  // s): moving islands of several bodies whose warm starts carry their points (9.6e-15 m at
  // 90° and 1.3e-14 m at 37°; the landing after it: kNotYet)
  ExpectTurnedMotion("dominoes.yaml", {"duration=0.33"});
}

TEST(RotationInvarianceTest, CubeFallsIntoTheCupTheSameWayTurned) {
  // a cube tumbling onto the floor of a cup made of five parts, 1 s (ecpsim_rotation_check:
  // 2.4e-14 m at 90°, 3.3e-13 m at 37°)
  ExpectTurnedMotion("cube_in_cup.yaml");
}

TEST(RotationInvarianceTest, CubeFallsIntoTheMugTheSameWayTurned) {
  // a cube tumbling onto the floor of a mug whose 12 parts the loader decomposed, 1 s
  // (ecpsim_rotation_check: 1.8e-13 m at 90°, 1.0e-13 m at 37°)
  ExpectTurnedMotion("cube_in_mug.yaml");
}

TEST(RotationInvarianceTest, CubeFallsOntoTheDumbbellsBarTheSameWayTurned) {
  // a cube dropped onto the bar of a dumbbell whose 3 parts the loader decomposed within a
  // tolerance, 1 s (ecpsim_rotation_check: 5.0e-15 m at 90°, 4.9e-15 m at 37°)
  ExpectTurnedMotion("cube_on_dumbbell.yaml");
}

TEST(RotationInvarianceTest, PegFallsIntoTheHoleTheSameWayTurned) {
  // a peg pushed by a kinematic finger onto the wall of a hole through a block of four parts,
  // sliding down it onto the table, 0.6 s (ecpsim_rotation_check: 3.3e-12 m at 90°, 5.2e-12 m at
  // 37°)
  ExpectTurnedMotion("peg_in_hole.yaml");
}

TEST(RotationInvarianceTest, GripperUnderTheLeastEnergySelectionGraspsTheSameWayTurned) {
  // the jaws close on the box, hold it and start dragging it (1.2 s of the scene's 3): with the
  // creep the pads' ECPs land where the Newton path takes them (6.5e-6 m apart over the whole
  // run); the least-energy selection picks one root whatever the frame (engine/README.md, "Steps
  // whose solutions form a set")
  ExpectTurnedMotion("gripper.yaml", {"duration=1.2", "solver.selection=least_energy"});
}

TEST(RotationInvarianceTest, TBarPushUnderTheLeastEnergySelectionMovesTheSameWayTurned) {
  // the finger's first touch of the T lying on the table (0.29 s), a step whose roots form a set,
  // its push and its turn across the T from 2.6 s: the scene's whole 4 s
  ExpectTurnedMotion("tbar_push.yaml", {"solver.selection=least_energy"});
}

TEST(RotationInvarianceTest, EveryMultiBodySceneIsAssertedOrListed) {
  // a new shipped multi-body scene joins one of the lists (and engine/README.md's paragraph)
  std::vector<std::string> listed = kAsserted;
  listed.insert(listed.end(), kNotYet.begin(), kNotYet.end());
  std::sort(listed.begin(), listed.end());
  EXPECT_EQ(testing::MultiBodyScenes(std::string(ECPSIM_SOURCE_DIR) + "/scenes"), listed);
}

}  // namespace
}  // namespace ecpsim::engine
