#pragma once
// One time step of a scene with its contact model.

#include "common/cancel_flag.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// Advances `state` by scene.h with the scene's contact model, island by island, with warm start,
/// the restart ladder and h/2, h/4, h/16 sub-steps on failure (engine/README.md), working in the
/// caller's `workspace` (keep one for a run: its steps then allocate nothing of their own).
/// @throws SolverFailure naming time, body and residual; ModelInvalid where the model does not
///         apply; Cancelled (StopStepsOn). `state` is then unchanged.
StepReport Step(const Scene& scene, State& state, StepWorkspace& workspace);

/// Steps in `workspace` stop within a solver iteration once `flag` is raised (null: never; e.g.
/// by a signal handler or a CPU watchdog, common/cancel_flag.h), throwing Cancelled with `state`
/// unchanged.
void StopStepsOn(StepWorkspace& workspace, const CancelFlag* flag);

/// Step in a workspace of its own for this one step (allocates: for one-off steps).
StepReport Step(const Scene& scene, State& state);

}  // namespace ecpsim::engine
