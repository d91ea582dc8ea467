// Under the least-energy selection, the last step's selected root is verified first on the
// step's exact problem, as the creep's warm start is on its own (engine/README.md, "Steps whose
// solutions form a set", "A selected start that holds"): scenes/train.yaml's row pushed at the
// pusher's speed then takes no Newton iteration a step once it moves on as it did, where taking
// the root off the exact set with the creep and back again took 48 a step (76.9 s of CPU for the
// scene's 2 s, 7.2 s with the verified start). Which step the start first holds in depends on the
// path: the strike's creep root, taken to the least energy, gave selected roots that the next
// step verified from 0.15 s while the island's LU was Eigen's SparseLU, and gives ones whose
// exact residual at the next step is 0.13–0.57 until 0.55 s since it is KLU's (engine/README.md,
// "The island's linear algebra": the selection's end depends on its start where it stops
// unconverged, "Steps whose solutions form a set").

#include <string>

#include <gtest/gtest.h>

#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// s: the row moves on as it did, and its selected start holds, from here (the strike at t = 0,
// the row's settling by 0.18 s, the selected start first holding at 0.55 s)
constexpr double kSettled = 0.6;
constexpr double kUntil = 0.8;  // s
// m/s: the first box at the pusher's speed, to the solve's tolerance over the velocity scale
constexpr double kSpeedRoundOff = 1e-12;

TEST(SelectedStartTest, ARowPushedAtTheFingersSpeedTakesNoNewtonIterationUnderTheSelection) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/train.yaml",
                                {"solver.selection=least_energy"})
                          .scene;
  const int first_box = 0, pusher = static_cast<int>(scene.bodies.size()) - 1;
  ASSERT_TRUE(scene.bodies[pusher].IsKinematic());
  State state = InitialState(scene);
  StepWorkspace workspace;
  while (state.t < kUntil) {
    const StepReport report = Step(scene, state, workspace);
    ASSERT_TRUE(report.converged) << "t = " << state.t;
    if (state.t < kSettled) continue;
    EXPECT_EQ(report.iterations, 0) << "t = " << state.t;
    EXPECT_NEAR(state.bodies[first_box].v_WB.x(), state.bodies[pusher].v_WB.x(), kSpeedRoundOff)
        << "t = " << state.t;
  }
}

}  // namespace
}  // namespace ecpsim::engine
