// The hull model's restart ladder on steps whose warm start is good (engine/README.md, "The first
// pass's warm start"): Newton from the last step's solution converges at its own rate.

#include "engine/hull_model.h"

#include <gtest/gtest.h>

#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

// Newton iterations per step of a box sliding to rest at constant deceleration: from the last
// step's solution only ν⁺ and the friction impulse's balance change, by μ g h, and Newton's first
// step lands within the tolerance (measured: 1 per step). With the Jacobian smoothing of the later
// guesses (0.1 ‖Φ‖) the Newton matrix is off by that much and it took 3; 2 leaves one for margin
constexpr int kMaxSlidingIterations = 2;

TEST(HullModelTest, ABoxSlidingToRestTakesOneNewtonIterationPerStep) {
  // box 0.5 × 0.5 × 0.1 m, 15 kg, μ = 0.22, v0 = 0.5 m/s along +x: it stops at t* = 0.23 s
  Body box = testing::MakeBoxBody(Vector3d(0.5, 0.5, 0.1), 15);
  box.p0 = Vector3d(0, 0, 0.05);
  box.v0 = Vector3d(0.5, 0, 0);
  Scene scene = testing::MakeGroundScene({box});
  scene.model = ContactModel::kHull;
  State state = InitialState(scene);
  ASSERT_TRUE(Step(scene, state).converged);  // the first step starts from free flight
  int compared = 0;
  while (state.t < 0.2) {
    const StepReport report = Step(scene, state);
    ASSERT_TRUE(report.converged) << "t = " << state.t;
    EXPECT_LE(report.iterations, kMaxSlidingIterations) << "t = " << state.t;
    ++compared;
  }
  EXPECT_GE(compared, 18);
  EXPECT_GT(state.bodies[0].v_WB.x(), 0);  // still sliding
}

}  // namespace
}  // namespace ecpsim::engine
