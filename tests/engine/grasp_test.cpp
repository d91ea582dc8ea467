// A box lifted between two flat pads (scenes/gripper.yaml's gripper, issue 33's reproducer) with
// `solver.selection: least_energy`: it holds while the pads' friction 2 μ F exceeds its weight
// m g, and stays on the table while the pads slide up along it once 2 μ F < m g; held off
// centre, it turns out of the grip where the weight's moment exceeds the pads' torsion.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "engine/report/penetration.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

constexpr double kMu = 0.5;        // the pads' friction
constexpr double kMass = 0.2;      // kg, the scene's box
constexpr double kG = 9.8;         // m/s²
constexpr double kLiftFrom = 0.5;  // s: the frame rises 2 cm from here at 0.04 m/s ...
constexpr double kLiftEnd = 1.0;   // s: ... to here
// m and rad: a held box moves with the jaws to the solver's tolerance (1e-12 of the lengths and
// velocities) summed over a hundred steps, with margin; no creep is left to drift
constexpr double kHeld = 1e-9;
// m: no hull inside another beyond the solver's position error (1e-12 of the lengths)
constexpr double kPenetration = 1e-9;

// the grip `ratio` × m g / (2 μ) from 0.3 s; the frame rises from 0.04 m at kLiftFrom to `top` at
// kLiftEnd. A lift of 2 cm jerks the jaws to 0.04 m/s in one step, which asks the pads for
// m (g h + 0.04 m/s) = 0.0276 N·s of their 2 μ F h
Scene GraspScene(double ratio, double top = 0.06) {
  const double force = ratio * kMass * kG / (2 * kMu);
  return LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/gripper.yaml",
                   {"duration=1", "solver.selection=least_energy",
                    fmt::format("pairs.0.friction.mu={}", kMu),
                    fmt::format("pairs.1.friction.mu={}", kMu),
                    fmt::format("grippers.0.force=\"t < 0.3 ? 0.2 : {}\"", force),
                    fmt::format("grippers.0.motion.waypoints=[{{t: {}, position: [0, 0, 0.04]}}, "
                                "{{t: {}, position: [0, 0, {}]}}]",
                                kLiftFrom, kLiftEnd, top)})
      .scene;
}

int BodyIndex(const Scene& scene, const std::string& name) {
  for (size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].name == name) return static_cast<int>(b);
  ADD_FAILURE() << "no body " << name;
  return 0;
}

// steps `scene` to its end, expecting the box to ride with the jaws from kLiftFrom (its height
// above them kept, upright, to kHeld) and no penetration; the final state
State ExpectRidesWithTheJaws(const Scene& scene) {
  const int box = BodyIndex(scene, "box"), jaw = BodyIndex(scene, "left_jaw");
  const PenetrationProbe probe(scene);
  State state = InitialState(scene);
  double offset = NAN;  // the box's height above the jaw when the lift starts
  while (state.t < scene.duration - 0.5 * scene.h) {
    if (!Step(scene, state).converged) {
      ADD_FAILURE() << "t = " << state.t;
      break;
    }
    EXPECT_LE(probe.MaxDepth(scene, state), kPenetration) << "t = " << state.t;
    const BodyState& b = state.bodies[box];
    if (state.t < kLiftFrom - 0.5 * scene.h) continue;
    const double above = b.p_WB.z() - state.bodies[jaw].p_WB.z();
    if (std::isnan(offset)) offset = above;
    EXPECT_NEAR(above, offset, kHeld) << "t = " << state.t;
    EXPECT_LE(2 * Eigen::AngleAxisd(b.Q_WB).angle(), kHeld) << "t = " << state.t;
  }
  return state;
}

TEST(GraspTest, ABoxHeldWithFrictionToSpareRisesWithTheJawsWithoutSlipOrTurn) {
  const Scene scene = GraspScene(1.53);  // the reproducer: 2 μ F = 3 N against 1.96 N
  const State state = ExpectRidesWithTheJaws(scene);
  EXPECT_NEAR(state.bodies[BodyIndex(scene, "box")].p_WB.z(), 0.06, kHeld);  // lifted 2 cm
}

TEST(GraspTest, ALiftThatJerksFasterThanFrictionAllowsSlipsByCoulombsAmountOnly) {
  // the reproducer: 5 cm at 0.1 m/s. In the lift's first step the pads give the box at
  // most 2 μ F h − m g h of momentum, so it lags the jaws by (v − (2 μ F − m g) h / m) h; from the
  // next step on it needs less than the pads' friction, and rides with them, upright
  const double ratio = 1.53, speed = 0.1;
  const Scene scene = GraspScene(ratio, 0.09);
  const int box = BodyIndex(scene, "box"), jaw = BodyIndex(scene, "left_jaw");
  const double force = ratio * kMass * kG / (2 * kMu);
  const double lag = (speed - (2 * kMu * force - kMass * kG) * scene.h / kMass) * scene.h;
  State state = InitialState(scene);
  double offset = NAN;
  while (state.t < scene.duration - 0.5 * scene.h) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    const BodyState& b = state.bodies[box];
    const double above = b.p_WB.z() - state.bodies[jaw].p_WB.z();
    if (state.t < kLiftFrom + 0.5 * scene.h) {  // the frame has not moved yet
      offset = above;
      continue;
    }
    EXPECT_NEAR(above, offset - lag, kHeld) << "t = " << state.t;
    EXPECT_LE(2 * Eigen::AngleAxisd(b.Q_WB).angle(), kHeld) << "t = " << state.t;
  }
}

TEST(GraspTest, ABoxHeldTooWeaklyStaysOnTheTableAsThePadsSlideUp) {
  const Scene scene = GraspScene(0.9);
  const int box = BodyIndex(scene, "box"), jaw = BodyIndex(scene, "left_jaw");
  State state = InitialState(scene);
  while (state.t < scene.duration - 0.5 * scene.h) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    EXPECT_NEAR(state.bodies[box].p_WB.z(), 0.04, kPenetration) << "t = " << state.t;
    // while the pads slide up along it the table carries its weight less their friction 2 μ F
    // (box–ground is the scene's first contact)
    if (state.t > kLiftFrom + 1.5 * scene.h && state.t < kLiftEnd - 0.5 * scene.h) {
      EXPECT_NEAR(state.contacts[0].p_n, (1 - 0.9) * kMass * kG * scene.h, kHeld * kMass)
          << "t = " << state.t;
    }
  }
  EXPECT_NEAR(state.bodies[jaw].p_WB.z(), 0.06, kHeld);  // the jaws rose 2 cm along the box
}

TEST(GraspTest, ASlowLiftJustAboveSlipOnsetHoldsWithoutTurning) {
  // 2 μ F = 1.03 m g lifting at 1 mm/s: the pads' spare friction gives the jaws' speed in one
  // step, so the box rides with them. (The selection once left this grasp's piece of the set for
  // a slipping one whose pads' ECPs sat 9 mm off centre, and the box turned 4e-3 rad)
  ExpectRidesWithTheJaws(GraspScene(1.03, 0.0405));
}

// A grip of pads `pad` (m, across and along the lift) whose centre is `offset` (m) beside the
// box's CM: slip begins where 2 μ F = m g √(1 + (c / e_r)²), c the offset of the centroid of the
// pad's overlap with the box's face (each pad carries m g / 2 along the lift and m g c / 2 about
// its normal, on the ellipsoid (f / μ F)² + (τ / (e_r μ F))² = 1).
struct SlipOnsetCase {
  double pad_across, pad_along, offset;
};

class SlipOnsetTest : public testing::TestWithParam<SlipOnsetCase> {};

constexpr double kPadTorsion = 0.01;     // m, the scene's pads' e_r
constexpr double kBoxHalfWidth = 0.025;  // m
// slip onset against the prediction (the issue asks for 2 %). Measured (examples/grasp_slip.py):
// within one ramp step (0.58 %) where the grip is centred, off centre within 0.63 % but at 5 mm
// (1.1–1.7 % early for 2 cm pads, 0.6–1.2 % late for 4 cm ones), where the held piece's least
// point is found to the selection's tolerance rather than exactly at the friction limit and the
// piece the ramp goes on in depends on the roots before it; these five cases slip within 1 %
constexpr double kOnsetTolerance = 0.01;
// the grip from kLiftFrom: kRampStart × the prediction while the frame lifts 5 mm at 12.5 mm/s
// (a jerk the spare friction takes in one step, so the box starts the ramp as placed) until
// kRampFrom, then less by kRampRate of it per second. Slip shows as a move or turn relative to the
// jaws of more than kHeld in a step; the step's force (taken at its start) and the last held
// step's bracket the onset
constexpr double kRampStart = 1.15, kRampFrom = 1.0, kRampRate = 0.5;

TEST_P(SlipOnsetTest, SlipBeginsWhereThePadsFrictionEllipsoidNoLongerHoldsTheWeight) {
  const SlipOnsetCase& c = GetParam();
  const double half = 0.5 * c.pad_across;
  const double lo = std::max(c.offset - half, -kBoxHalfWidth);
  const double hi = std::min(c.offset + half, kBoxHalfWidth);
  const double centroid = 0.5 * (lo + hi);
  const double predicted = kMass * kG * std::hypot(1.0, centroid / kPadTorsion) / (2 * kMu);  // N
  const std::string pad = fmt::format("[0.01, {}, {}]", c.pad_across, c.pad_along);
  const Scene scene =
      LoadScene(
          std::string(ECPSIM_SOURCE_DIR) + "/scenes/gripper.yaml",
          {"duration=1.6", "solver.selection=least_energy",
           fmt::format("pairs.0.friction.mu={}", kMu), fmt::format("pairs.1.friction.mu={}", kMu),
           fmt::format("pairs.0.friction.e_r={}", kPadTorsion),
           fmt::format("pairs.1.friction.e_r={}", kPadTorsion), "bodies.1.shape.box.size=" + pad,
           "bodies.2.shape.box.size=" + pad,
           fmt::format("bodies.1.position=[-0.05, {}, 0.04]", c.offset),
           fmt::format("bodies.2.position=[0.05, {}, 0.04]", c.offset),
           fmt::format("grippers.0.force=\"t < 0.3 ? 0.2 : {} * (t < {} ? 1 : 1 - {} * "
                       "(t - {}))\"",
                       kRampStart * predicted, kRampFrom, kRampRate, kRampFrom),
           fmt::format("grippers.0.motion.waypoints=[{{t: {}, position: [0, {}, 0.04]}}, "
                       "{{t: 0.9, position: [0, {}, 0.045]}}]",
                       kLiftFrom, c.offset, c.offset)})
          .scene;
  const int box = BodyIndex(scene, "box"), jaw = BodyIndex(scene, "left_jaw");
  State state = InitialState(scene);
  double offset = NAN, held_force = NAN;
  Eigen::Quaterniond held_turn = Eigen::Quaterniond::Identity();
  while (state.t < scene.duration - 0.5 * scene.h) {
    const double force = scene.grippers[0].force(state.t);
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    if (state.t < kRampFrom - 0.5 * scene.h) continue;
    const BodyState& b = state.bodies[box];
    const double above = b.p_WB.z() - state.bodies[jaw].p_WB.z();
    if (std::isnan(offset)) {
      offset = above;
      held_turn = b.Q_WB;
    }
    if (std::abs(above - offset) > kHeld ||
        2 * Eigen::AngleAxisd(held_turn.inverse() * b.Q_WB).angle() > kHeld) {
      ASSERT_FALSE(std::isnan(held_force)) << "slipped when the ramp began";
      EXPECT_LT(force, predicted * (1 + kOnsetTolerance)) << "held at " << held_force << " N";
      EXPECT_GE(held_force, predicted * (1 - kOnsetTolerance)) << "slipped at " << force << " N";
      return;
    }
    held_force = force;
  }
  ADD_FAILURE() << "held to " << held_force << " N, predicted to slip below " << predicted << " N";
}

INSTANTIATE_TEST_SUITE_P(
    Grips, SlipOnsetTest,
    testing::Values(SlipOnsetCase{0.04, 0.03, 0}, SlipOnsetCase{0.02, 0.015, 0},
                    SlipOnsetCase{0.04, 0.03, 0.005}, SlipOnsetCase{0.02, 0.015, 0.005},
                    SlipOnsetCase{0.04, 0.03, 0.01}),
    [](const testing::TestParamInfo<SlipOnsetCase>& param) {
      return fmt::format("Pads{:.0f}mmOffset{:.0f}mm", param.param.pad_across * 1e3,
                         param.param.offset * 1e3);
    });

}  // namespace
}  // namespace ecpsim::engine
