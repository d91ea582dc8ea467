#pragma once
// The one loop every contact model runs in: the scene's contact islands, each advanced by its
// model at h, else as 2 sub-steps of h/2, 4 of h/4, 16 of h/16, on the workspace's threads; the
// state committed only when every island is solved; kinematic bodies moved to their prescribed
// poses.

#include <functional>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// Calls `use` with a contact model's stepper working in `workspace` (each thread has its own).
using WithModel = std::function<void(StepWorkspace& workspace,
                                     const std::function<void(const ContactModelStepper&)>& use)>;

/// One step of `scene`, island by island, each island solved by the stepper `with_model` gives
/// the thread that takes it, on the threads of `workspace` (IslandThreadsOf; the result is the
/// same whatever their number); a contact left out of every island (its bodies apart) reports no
/// impulse.
/// @throws SolverFailure with the StepFailure of the first island (by index) that failed (its
///         message FormatStepFailure's); ModelInvalid from the model; InputError from a
///         kinematic body's motion (an expression not finite at t). `state` is then unchanged.
StepReport StepIslands(const Scene& scene, State& state, const WithModel& with_model,
                       StepWorkspace& workspace);

}  // namespace ecpsim::engine
