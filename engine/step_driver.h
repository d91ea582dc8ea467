#pragma once
// The one loop every contact model runs in: the scene's contact islands, each advanced by its
// model at h, else as 2 sub-steps of h/2, 4 of h/4, 16 of h/16; the state committed only when
// every island is solved; kinematic bodies moved to their prescribed poses.

#include <vector>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// The scene's islands for the step [t, t + h] from `state` (in order of their lowest body):
/// the broad phase bounds each body by a world box holding its hull and everything it can reach
/// within the step (its own speed, spin, loads and gravity over h, plus what the fastest body of
/// the scene can give it); a kinematic body's box holds its hull at the step's two ends. A
/// contact between two bodies whose boxes overlap is in the step (two dynamic bodies then share
/// an island); one whose boxes are apart is not, and its bodies cannot touch within the step. Every dynamic body is in exactly one island, with all its contacts with obstacles;
/// kinematic bodies are in none (their motion is given).
std::vector<Island> FormIslands(const Scene& scene, const State& state);

/// One step of `scene` with `model`, island by island; a contact left out of every island (its
/// bodies apart) reports no impulse.
/// @throws SolverFailure "<prefix>solver failed at t = … on body '…': residual … > tolerance …;
///         tried …"; ModelInvalid from the model; InputError from a kinematic body's motion
///         (an expression not finite at t). `state` is then unchanged.
StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model);

}  // namespace ecpsim::engine
