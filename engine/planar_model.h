#pragma once
// The planar sliding model of Xie & Chakraborty (WAFR 2018): a body resting flat on a horizontal
// plane, sliding and turning without vertical motion or tipping; a few quadratic equations per
// step. Valid only while the ECP stays inside the support face and p_n > 0.

#include <stdexcept>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// The planar model does not apply to the scene or stopped applying during the run: the body is
/// not flat on a horizontal plane, would lift off (p_n ≤ 0), or its ECP left the support face
/// (it would tip). The message names time, body and the violated condition.
class ModelInvalid : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One step of the planar sliding model for every body (FORMULATION.md, "The planar-sliding
/// model"). Unknowns p_t, p_o, p_r, σ per body; p_n = m g h − p_z (no vertical motion), the ECP at
/// r = ((p_τy − q_z p_t)/p_n, −(q_z p_o + p_τx)/p_n) from the CM projection (zero tipping moment),
/// friction in Fritz-John form with the cone written as μ p_n − ‖p̂‖ (engine/README.md).
/// @throws ModelInvalid when the model's assumptions fail; SolverFailure if the 4×4 problem
///         does not converge. `state` is unchanged then.
StepReport StepPlanarSliding(const Scene& scene, State& state);

}  // namespace ecpsim::engine
