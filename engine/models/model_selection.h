#pragma once
// Which contact model steps a scene: the stepper of Scene::model, after the checks that the
// model can handle the scene's kinds of contact.

#include <functional>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// Calls `use` with the stepper of `scene.model` for `scene` working in `workspace`, built in
/// place for the call (a time step's stepper costs no heap allocation).
/// @throws ModelInvalid where the model does not apply to the scene.
void UseContactModel(const Scene& scene, StepWorkspace& workspace,
                     const std::function<void(const ContactModelStepper&)>& use);

}  // namespace ecpsim::engine
