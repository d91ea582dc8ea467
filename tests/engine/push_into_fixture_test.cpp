// Bodies pushed by a force into fixed box fixtures at the paper's h = 0.01 s (issue 13: "a push
// into a wall, into a corner … run at h = 0.01 without a solver failure"; a T-bar pushed into a
// box fixture by 10 N off its CM once needed 15 restarts and 430 iterations in one step, and
// failed on another machine). Each body must come to rest against the fixtures it is pushed
// into, without penetrating them or the ground.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "engine/report/penetration.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;

// m: no mesh vertex inside an obstacle beyond the solver's position error (1e-12 of the
// lengths) with margin (as tests/engine/manipulation_scenes_test.cpp)
constexpr double kPenetration = 1e-9;
// m/s: at rest, pressed into the fixtures: every velocity the steps leave is the solver's
// residual (1e-12 of the velocity scale g h ≈ 0.1 m/s) times the rows it sums, with margin
constexpr double kRestSpeed = 1e-9;
// a contact normal is solved with the step: a unit vector to the solver's precision, with margin
constexpr double kNormalTol = 1e-9;

// `yaml` as a scene file next to the repository's scenes/ (its meshes/ paths resolve there)
Scene SceneFromText(const std::string& name, const std::string& yaml) {
  const fs::path path = fs::temp_directory_path() / (name + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << yaml;
  Scene scene = LoadScene(path.string()).scene;
  fs::remove(path);
  return scene;
}

// steps `scene` to its end, each step converged and nothing inside anything
void RunWithoutPenetration(const Scene& scene, State& state) {
  const PenetrationProbe probe(scene);
  while (state.t < scene.duration - 0.5 * scene.h) {
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    ASSERT_LE(probe.MaxDepth(scene, state), kPenetration) << "t = " << state.t;
  }
}

TEST(PushIntoFixtureTest, ATBarPushedOffItsCentreIntoAWallComesToRestAgainstIt) {
  // the paper's T-bar flat on the table, 10 N along +x applied 5 cm beside its CM: it slides
  // and turns into a wall 2 cm ahead of it until it rests pressed against it
  const Scene scene = SceneFromText("tbar_wall", fmt::format(R"yaml(
h: 0.01
duration: 3
ground: {{friction: {{mu: 0.22, e_t: 1, e_o: 1, e_r: 0.1}}}}
obstacles:
  - name: wall
    box: {{size: [0.1, 1, 0.3], position: [0.335, 0, 0.15]}}
    friction: {{mu: 0.3, e_t: 1, e_o: 1, e_r: 0.02}}
bodies:
  - name: tbar
    mesh: {}/scenes/meshes/tbar.obj
    mass: 2
    rpy: [0, 0, 90]
    on_ground: true
    position: [0, 0]
loads:
  - {{body: tbar, force: [10, 0, 0], at: [0, 0.05, 0]}}
)yaml",
                                                             ECPSIM_SOURCE_DIR));
  State state = InitialState(scene);
  RunWithoutPenetration(scene, state);
  const BodyState& T = state.bodies[0];
  EXPECT_LE(T.v_WB.norm() + T.w_WB.norm(), kRestSpeed);
  // pressed against the wall: the force of the load balanced by the wall's normal impulse (and
  // the ground's friction, which at rest carries nothing along x beyond what the wall leaves)
  const ContactState& wall = state.contacts[1];
  EXPECT_GT(wall.p_n, 0);
  EXPECT_NEAR(wall.n.x(), -1, kNormalTol);  // the wall's −x face
}

TEST(PushIntoFixtureTest, ABoxPushedDiagonallyIntoACornerComesToRestTouchingBothWalls) {
  // a 0.2 m box pushed along (1, 1) into the corner of two walls 5 cm from its faces
  const Scene scene = SceneFromText("box_corner", R"yaml(
h: 0.01
duration: 2
ground: {friction: {mu: 0.3, e_t: 1, e_o: 1, e_r: 0.05}}
obstacles:
  - name: east
    box: {size: [0.1, 1, 0.3], position: [0.2, 0, 0.15]}
  - name: north
    box: {size: [1, 0.1, 0.3], position: [0, 0.2, 0.15]}
bodies:
  - name: box
    shape: {box: {size: [0.2, 0.2, 0.1]}}
    mass: 1
    position: [0, 0, 0.05]
    rpy: [0, 0, 5]
loads:
  - {body: box, force: [6, 6, 0]}
)yaml");
  State state = InitialState(scene);
  RunWithoutPenetration(scene, state);
  const BodyState& box = state.bodies[0];
  EXPECT_LE(box.v_WB.norm() + box.w_WB.norm(), kRestSpeed);
  // both walls push back, and the box has turned square into the corner: its faces flat on
  // the walls' faces at x = y = 0.15
  EXPECT_GT(state.contacts[1].p_n, 0);
  EXPECT_GT(state.contacts[2].p_n, 0);
  EXPECT_NEAR(box.p_WB.x(), 0.05, kPenetration);
  EXPECT_NEAR(box.p_WB.y(), 0.05, kPenetration);
}

}  // namespace
}  // namespace ecpsim::engine
