// The caller's step memory: parts made once and kept, copies that start empty, and steps whose
// bits do not depend on what earlier steps left in the workspace.

#include "engine/step_workspace.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using testing::MakeBoxBody;
using testing::MakeGroundScene;

TEST(StepWorkspaceTest, APartIsMadeOnceAndKept) {
  StepWorkspace workspace;
  std::vector<double>& part = workspace.Part<std::vector<double>>();
  part.assign(3, 1.5);
  workspace.Part<std::vector<int>>().assign(2, 7);  // another type: another part
  EXPECT_EQ(&workspace.Part<std::vector<double>>(), &part);
  EXPECT_EQ(workspace.Part<std::vector<double>>().size(), 3u);
  EXPECT_EQ(workspace.Part<std::vector<int>>().size(), 2u);
}

TEST(StepWorkspaceTest, ACopyStartsEmptyAndAMoveKeepsTheParts) {
  StepWorkspace workspace;
  workspace.Part<std::vector<double>>().assign(3, 1.5);
  const StepWorkspace copy = workspace;
  EXPECT_TRUE(StepWorkspace(copy).Part<std::vector<double>>().empty());
  StepWorkspace assigned;
  assigned.Part<std::vector<double>>().assign(1, 2.0);
  assigned = workspace;
  EXPECT_TRUE(assigned.Part<std::vector<double>>().empty());
  StepWorkspace moved = std::move(workspace);
  EXPECT_EQ(moved.Part<std::vector<double>>().size(), 3u);
}

TEST(StepWorkspaceTest, OneWorkspaceForTwoScenesGivesTheBitsOfOneEach) {
  // a tumbling box and a sliding one stepped alternately in one workspace, against each in a
  // fresh workspace every step: the same bits
  Body tumbling = MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 2);
  tumbling.p0 = Vector3d(0, 0, 0.2);
  tumbling.v0 = Vector3d(0.4, 0.1, 0);
  tumbling.w0 = Vector3d(0.5, 1, 2);
  Body sliding = MakeBoxBody(Vector3d(0.1, 0.1, 0.1), 1);
  sliding.p0 = Vector3d(0, 0, 0.05);
  sliding.v0 = Vector3d(1, 0, 0);
  const std::vector<Scene> scenes = {MakeGroundScene({tumbling}), MakeGroundScene({sliding})};
  std::vector<State> shared, fresh;
  for (const Scene& scene : scenes) {
    shared.push_back(InitialState(scene));
    fresh.push_back(InitialState(scene));
  }
  StepWorkspace workspace;
  for (int i = 0; i < 40; ++i) {
    for (size_t s = 0; s < scenes.size(); ++s) {
      Step(scenes[s], shared[s], workspace);
      Step(scenes[s], fresh[s]);
      ASSERT_EQ(shared[s].bodies[0].p_WB, fresh[s].bodies[0].p_WB) << "scene " << s;
      ASSERT_EQ(shared[s].bodies[0].Q_WB.coeffs(), fresh[s].bodies[0].Q_WB.coeffs());
      ASSERT_EQ(shared[s].bodies[0].v_WB, fresh[s].bodies[0].v_WB);
    }
  }
}

TEST(StepWorkspaceTest, SparseIslandsInOneWorkspaceGiveTheBitsOfOneEach) {
  // the train's strike (a pusher meeting a row of six boxes: an island of 264 unknowns, solved
  // sparse) in two variants of one layout, whose Newton matrices differ in their non-zeros,
  // stepped alternately in one workspace and each in a fresh one: a sparse factorization's kept
  // analysis must not carry one island's pattern into the other's factors
  const std::string path = std::string(ECPSIM_SOURCE_DIR) + "/scenes/train.yaml";
  const std::vector<Scene> scenes = {
      LoadScene(path).scene, LoadScene(path, {"bodies.1.mass=1.7", "bodies.4.mass=0.6"}).scene};
  std::vector<State> shared, fresh;
  for (const Scene& scene : scenes) {
    shared.push_back(InitialState(scene));
    fresh.push_back(InitialState(scene));
  }
  StepWorkspace workspace;
  for (int i = 0; i < 15; ++i) {
    for (size_t s = 0; s < scenes.size(); ++s) {
      Step(scenes[s], shared[s], workspace);
      Step(scenes[s], fresh[s]);
      for (size_t b = 0; b < scenes[s].bodies.size(); ++b) {
        ASSERT_EQ(shared[s].bodies[b].p_WB, fresh[s].bodies[b].p_WB) << "scene " << s;
        ASSERT_EQ(shared[s].bodies[b].v_WB, fresh[s].bodies[b].v_WB) << "scene " << s;
      }
    }
  }
}

}  // namespace
}  // namespace ecpsim::engine
