// A box lifted between two flat pads (scenes/gripper.yaml's gripper, issue 33's reproducer) with
// `solver.selection: least_energy`: it holds while the pads' friction 2 μ F exceeds its weight
// m g, and stays on the table while the pads slide up along it once 2 μ F < m g.

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
                    fmt::format("grippers.0.motion.waypoints=[{{t: 0.5, position: [0, 0, 0.04]}}, "
                                "{{t: 1.0, position: [0, 0, {}]}}]",
                                top)})
      .scene;
}

int BodyIndex(const Scene& scene, const std::string& name) {
  for (size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].name == name) return static_cast<int>(b);
  ADD_FAILURE() << "no body " << name;
  return 0;
}

TEST(GraspTest, ABoxHeldWithFrictionToSpareRisesWithTheJawsWithoutSlipOrTurn) {
  const Scene scene = GraspScene(1.53);  // the reproducer: 2 μ F = 3 N against 1.96 N
  const int box = BodyIndex(scene, "box"), jaw = BodyIndex(scene, "left_jaw");
  const PenetrationProbe probe(scene);
  State state = InitialState(scene);
  double offset = NAN;  // the box's height above the jaw when the lift starts
  while (state.t < scene.duration - 0.5 * scene.h) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    ASSERT_LE(probe.MaxDepth(scene, state), kPenetration) << "t = " << state.t;
    const BodyState& b = state.bodies[box];
    if (state.t < kLiftFrom - 0.5 * scene.h) continue;
    const double above = b.p_WB.z() - state.bodies[jaw].p_WB.z();
    if (std::isnan(offset)) offset = above;
    EXPECT_NEAR(above, offset, kHeld) << "t = " << state.t;
    EXPECT_LE(2 * Eigen::AngleAxisd(b.Q_WB).angle(), kHeld) << "t = " << state.t;
  }
  EXPECT_NEAR(state.bodies[box].p_WB.z(), 0.06, kHeld);  // lifted the frame's 2 cm
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

}  // namespace
}  // namespace ecpsim::engine
