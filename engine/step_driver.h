#pragma once
// The one loop every contact model runs in: the scene's contact islands, each advanced by its
// model at h, else as 2 sub-steps of h/2, 4 of h/4, 16 of h/16; the state committed only when
// every island is solved; kinematic bodies moved to their prescribed poses.

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// One step of `scene` with `model`, island by island, in `workspace` (the one the model was
/// built with); a contact left out of every island (its
/// bodies apart) reports no impulse.
/// @throws SolverFailure with the island's StepFailure (its message FormatStepFailure's);
///         ModelInvalid from the model; InputError from a kinematic body's motion
///         (an expression not finite at t). `state` is then unchanged.
StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model,
                       StepWorkspace& workspace);

}  // namespace ecpsim::engine
