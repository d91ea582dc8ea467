#pragma once
// The per-body loop shared by the MNCP contact models: each body's step at h, then as 2 sub-steps
// of h/2, then 4 of h/4, then 16 of h/16, committing the state only when every body is solved.

#include <functional>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// Advances one body (its contacts `contacts`, in the order of `contact_ids`) from t by h. On
/// success returns true; either way sets `residual` to its last solve's and appends what it
/// tried to `tried`, and adds iterations and retries to `report`.
using AdvanceBody = std::function<bool(int body, const std::vector<int>& contact_ids, double t,
                                       double h, BodyState& state,
                                       std::vector<ContactState>& contacts, StepReport& report,
                                       double& residual, std::string& tried)>;

/// One step of `scene` for every body with `advance`.
/// @throws SolverFailure "<model_prefix>solver failed at t = … on body '…': residual … >
///         tolerance …; tried …"; `state` is then unchanged.
StepReport StepEveryBody(const Scene& scene, State& state, const std::string& model_prefix,
                         const AdvanceBody& advance);

}  // namespace ecpsim::engine
