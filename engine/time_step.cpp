#include "engine/time_step.h"

#include "engine/contact_model.h"
#include "engine/models/model_selection.h"
#include "engine/step_driver.h"

namespace ecpsim::engine {

StepReport Step(const Scene& scene, State& state) {
  StepReport report;
  UseContactModel(
      scene, [&](const ContactModelStepper& model) { report = StepIslands(scene, state, model); });
  return report;
}

}  // namespace ecpsim::engine
