// The caller's step memory: parts made once and kept, copies that start empty, and steps whose
// bits do not depend on what earlier steps left in the workspace.

#include "engine/step_workspace.h"

#include <vector>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace ecpsim::engine
