#include "engine/time_step.h"

#include "engine/contact_model.h"
#include "engine/step_driver.h"

namespace ecpsim::engine {

StepReport Step(const Scene& scene, State& state) {
  return StepIslands(scene, state, *MakeContactModel(scene));
}

}  // namespace ecpsim::engine
