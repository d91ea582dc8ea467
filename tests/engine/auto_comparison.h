#pragma once
// model: auto against model: hull run side by side (issue 11): the largest difference of their
// trajectories and how auto solved its steps; used by tests/engine/auto_model_test.cpp and
// tests/evaluation/stability_map_auto_test.cpp.

#include <algorithm>
#include <array>

#include "engine/step_report.h"
#include "engine/time_step.h"

namespace ecpsim::engine::testing {

struct AutoHullComparison {
  double difference = 0;                              // largest over bodies, steps, quantities
  std::array<long, engine::kNumStepModels> models{};  // auto's body-steps per model
  long steps = 0;                                     // steps both completed
  long auto_failed_at = -1, hull_failed_at = -1;      // step of a SolverFailure, −1: none
};

/// Runs `scene` with model auto and with model hull side by side for `steps` steps, or until one
/// of them fails (SolverFailure), or until a contact between two bodies carries an impulse when
/// `until_coupled` (there the hull model's own answer is determined only to the creep's
/// resolution: engine/README.md, "Bodies and contacts"). Differences in m, rad, m/s, rad/s.
inline AutoHullComparison CompareAutoWithHull(engine::Scene scene, long steps,
                                              bool until_coupled = false) {
  engine::Scene hull_scene = scene;
  scene.model = engine::ContactModel::kAuto;
  hull_scene.model = engine::ContactModel::kHull;
  engine::State a = engine::InitialState(scene), h = engine::InitialState(hull_scene);
  AutoHullComparison result;
  for (long k = 0; k < steps; ++k) {
    engine::StepReport report;
    try {
      report = engine::Step(scene, a);
    } catch (const engine::SolverFailure&) {
      result.auto_failed_at = k;
    }
    try {
      engine::Step(hull_scene, h);
    } catch (const engine::SolverFailure&) {
      result.hull_failed_at = k;
    }
    if (result.auto_failed_at >= 0 || result.hull_failed_at >= 0) break;
    if (until_coupled) {
      bool coupled = false;
      for (size_t c = 0; c < scene.contacts.size(); ++c)
        coupled |= scene.contacts[c].WithBody() && h.contacts[c].p_n > 0;
      if (coupled) break;
    }
    ++result.steps;
    for (engine::StepModel model : report.models) ++result.models[static_cast<int>(model)];
    for (size_t b = 0; b < a.bodies.size(); ++b) {
      const engine::BodyState& x = a.bodies[b];
      const engine::BodyState& y = h.bodies[b];
      result.difference =
          std::max({result.difference, (x.p_WB - y.p_WB).cwiseAbs().maxCoeff(),
                    x.Q_WB.angularDistance(y.Q_WB), (x.v_WB - y.v_WB).cwiseAbs().maxCoeff(),
                    (x.w_WB - y.w_WB).cwiseAbs().maxCoeff()});
    }
  }
  return result;
}

}  // namespace ecpsim::engine::testing
