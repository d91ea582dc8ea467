#pragma once
// The one loop every contact model runs in: the scene's contact islands, each advanced by its
// model at h, else as 2 sub-steps of h/2, 4 of h/4, 16 of h/16; the state committed only when
// every island is solved.

#include <vector>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// The scene's islands: every body with its contacts (a contact couples a body only with a fixed
/// obstacle, so each body is an island of its own), in body order.
std::vector<Island> FormIslands(const Scene& scene);

/// One step of `scene` with `model`, island by island.
/// @throws SolverFailure "<prefix>solver failed at t = … on body '…': residual … > tolerance …;
///         tried …"; ModelInvalid from the model. `state` is then unchanged.
StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model);

}  // namespace ecpsim::engine
