#include "engine/time_step.h"

#include "engine/contact_model.h"
#include "engine/models/model_selection.h"
#include "engine/step_driver.h"

namespace ecpsim::engine {

StepReport Step(const Scene& scene, State& state, StepWorkspace& workspace) {
  StepReport report;
  UseContactModel(scene, workspace, [&](const ContactModelStepper& model) {
    report = StepIslands(scene, state, model, workspace);
  });
  return report;
}

StepReport Step(const Scene& scene, State& state) {
  StepWorkspace workspace;
  return Step(scene, state, workspace);
}

}  // namespace ecpsim::engine
