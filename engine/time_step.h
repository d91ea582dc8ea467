#pragma once
// One time step of a scene with its contact model.

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// Advances `state` by scene.h with the scene's contact model, island by island, with warm start,
/// the restart ladder and h/2, h/4, h/16 sub-steps on failure (engine/README.md).
/// @throws SolverFailure naming time, body and residual; ModelInvalid where the model does not
///         apply. `state` is then unchanged.
StepReport Step(const Scene& scene, State& state);

}  // namespace ecpsim::engine
