#include "engine/models/auto_model.h"

#include <cmath>

#include <Eigen/Core>

#include "engine/models/planar_model.h"
#include "engine/solution_trend.h"
#include "engine/state.h"

namespace ecpsim::engine {

template <typename HullStep>
AdvanceResult AutoModel::PlanarElse(const Island& island, double t, double h, IslandState& state,
                                    const HullStep& hull_step) const {
  // (the planar model needs exactly one body on one obstacle)
  if (island.bodies.size() == 1 && island.contacts.size() == 1) {
    // the acceptance test (engine/README.md, "model: auto"): one body on one fixed plane,
    // moving in it and turning about its normal, the normal a principal axis, the support face
    // flat on the plane, the lowest point on it and the ECP on the face, all to the tolerance
    // in the body's own scales; a turn beyond π in a step is an alias the hull model refuses
    const double tolerance = scene_.solver.tolerance;
    // the point before the step, for the hull model's trend across planar steps
    // (the planar step leaves the warm start as it is)
    const auto* last = std::get_if<HullWarmStart>(&state.contacts[0].warm_start);
    const SolutionTrend::Point before =
        TrendPoint(state.bodies[0], state.contacts[0], last != nullptr ? last->s : 0.0);
    const PlanarStep step =
        SolvePlanarStep(scene_, island, t, h, {tolerance, tolerance, M_PI, tolerance}, state);
    if (step.invalid.empty() && step.result.solved) {
      // the hull model's unknowns at this solution, for when it takes over: a1 = a2 (s = 0), the
      // support face's multiplier 1 (its normal is −N), the plane's 1; and the trend on
      // (written over the last step's, whose storage it reuses)
      ContactState& c = state.contacts[0];
      const SolutionTrend trend =
          NextTrend(last != nullptr ? &last->trend : nullptr, before, TrendPoint(state.bodies[0], c, 0.0), h);
      auto* warm = std::get_if<HullWarmStart>(&c.warm_start);
      if (warm == nullptr) warm = &c.warm_start.emplace<HullWarmStart>();
      warm->s = 0;
      warm->l_g.setOnes(1);
      warm->window.assign(1, step.face);
      warm->l.setOnes(1);
      warm->other_window.clear();
      warm->trend = trend;
      return step.result;
    }
    AdvanceResult result = hull_step();
    result.iterations += step.result.iterations;
    return result;
  }
  return hull_step();
}

AdvanceResult AutoModel::Advance(const Island& island, double t, double h,
                                 IslandState& state) const {
  return PlanarElse(island, t, h, state, [&] { return hull_.Advance(island, t, h, state); });
}

std::optional<AdvanceResult> AutoModel::AdvanceAsLastResort(const Island& island, double t,
                                                            double h, IslandState& state) const {
  return PlanarElse(island, t, h, state,
                    [&] { return *hull_.AdvanceAsLastResort(island, t, h, state); });
}

}  // namespace ecpsim::engine
