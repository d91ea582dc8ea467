#include "engine/models/auto_model.h"

#include <cmath>

#include <Eigen/Core>

#include "engine/models/hull_attempt.h"
#include "engine/models/planar_model.h"
#include "engine/models/solution_trend.h"

namespace ecpsim::engine {

AdvanceResult AutoModel::Advance(const Island& island, double t, double h, IslandState& state,
                                 Effort effort) const {
  // (the planar model needs exactly one body on one obstacle)
  if (island.bodies.size() != 1 || island.contacts.size() != 1)
    return hull_.Advance(island, t, h, state, effort);
  // the acceptance test (engine/README.md, "model: auto"): one body on one fixed plane, moving in
  // it and turning about its normal, the normal a principal axis, the support face flat on the
  // plane, the lowest point on it and the ECP on the face, all to the tolerance in the body's own
  // scales; a turn beyond π in a step is an alias the hull model refuses
  const double tolerance = scene_.solver.tolerance;
  // the point before the step, for the hull model's trend across planar steps
  const SolutionTrend::Point before = hull::HullTrendPoint(state.bodies[0], state.contacts[0]);
  const PlanarStep step = SolvePlanarStep(
      scene_, island, t, h, {tolerance, tolerance, M_PI, tolerance}, state, workspace_);
  if (step.invalid.empty() && step.result.solved) {
    // the hull model's unknowns at this solution, for when it takes over
    hull::CommitFlatWarmStart(before, h, state.bodies[0], step.face, state.contacts[0]);
    return step.result;
  }
  AdvanceResult result = hull_.Advance(island, t, h, state, effort);
  result.iterations += step.result.iterations;
  return result;
}

}  // namespace ecpsim::engine
