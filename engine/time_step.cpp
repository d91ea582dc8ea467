#include "engine/time_step.h"

#include "engine/contact_model.h"
#include "engine/models/model_selection.h"
#include "engine/solver/complementarity_solver.h"
#include "engine/step_driver.h"

namespace ecpsim::engine {

StepReport Step(const Scene& scene, State& state, StepWorkspace& workspace) {
  return StepIslands(
      scene, state,
      [&](StepWorkspace& thread_workspace,
          const std::function<void(const ContactModelStepper&)>& use) {
        UseContactModel(scene, thread_workspace, use);
      },
      workspace);
}

void StopStepsOn(StepWorkspace& workspace, const CancelFlag* flag) {
  workspace.Part<McpWorkspace>().StopOn(flag);
}

StepReport Step(const Scene& scene, State& state) {
  StepWorkspace workspace;
  return Step(scene, state, workspace);
}

}  // namespace ecpsim::engine
