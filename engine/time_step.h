#pragma once
// One time step of the geometrically implicit MNCP scheme for every body of a scene.

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// Advances `state` by scene.h: solves one MNCP per body (its contacts coupled), with warm start,
/// the restart ladder and h/2, h/4, h/16 sub-steps on failure (engine/README.md).
/// @throws SolverFailure naming time, body and residual; `state` is then unchanged.
StepReport Step(const Scene& scene, State& state);

}  // namespace ecpsim::engine
