// The least-energy selection ends at the least point of a step's set, not short of it
// (engine/README.md, "Steps whose solutions form a set"): scenes/push_box.yaml's box rests on
// the table while the pusher comes into reach, and the selection's island then holds both. Of
// that step's solutions, the pusher taking some of the box's weight by its face's friction and
// the table the rest, the least energy leaves the whole weight on the table (the pusher's patch
// carries nothing). A selection whose landings give up before they land (too small a
// kNearSetStallIterations) stops short there: the table carried 0.4 % less of the weight, with
// a friction impulse, and the ECP 0.65 mm off the CM.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// s: the box at rest with the pusher in its island (its face reaches the box at 0.1 s)
constexpr double kResting = 0.1;
// of m g h and of the box's size: the least point to the solve's tolerance (1e-10), with room for
// the impulses' round-off over the island's scales
constexpr double kLeastPointRel = 1e-9;

TEST(LeastEnergyPointTest, ABoxAtRestBesideThePusherKeepsItsWholeWeightOnTheTable) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/push_box.yaml",
                                {"solver.selection=least_energy"})
                          .scene;
  const int box = 0;
  int ground = -1;
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    if (scene.contacts[k].body == box && !scene.contacts[k].WithBody())
      ground = static_cast<int>(k);
  ASSERT_GE(ground, 0);
  const double weight = scene.bodies[box].mass * std::abs(scene.gravity.z()) * scene.h;
  const double size = 0.2;  // m, the box's edge
  State state = InitialState(scene);
  StepWorkspace workspace;
  while (state.t < kResting - scene.h / 2) {
    const StepReport report = Step(scene, state, workspace);
    ASSERT_TRUE(report.converged) << "t = " << state.t;
    const ContactState& c = state.contacts[ground];
    EXPECT_NEAR(c.p_n, weight, kLeastPointRel * weight) << "t = " << state.t;
    EXPECT_NEAR(std::hypot(c.p_t, c.p_o), 0, kLeastPointRel * weight) << "t = " << state.t;
    const Eigen::Vector3d offset = c.a1 - state.bodies[box].p_WB;
    EXPECT_NEAR(std::hypot(offset.x(), offset.y()), 0, kLeastPointRel * size) << "t = " << state.t;
  }
}

}  // namespace
}  // namespace ecpsim::engine
