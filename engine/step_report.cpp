#include "engine/step_report.h"

#include <fmt/format.h>

namespace ecpsim::engine {

const char* StepModelName(StepModel model) {
  switch (model) {
    case StepModel::kFree:
      return "free";
    case StepModel::kPlanar:
      return "planar";
    case StepModel::kHull:
      return "hull";
    case StepModel::kMultiPatch:
      return "multipatch";
    case StepModel::kPoint:
      return "point";
    case StepModel::kParts:
      return "parts";
    case StepModel::kKinematic:
      break;
  }
  return "kinematic";
}

std::string FormatStepFailure(const StepFailure& failure) {
  std::string bodies, tried;
  for (const std::string& name : failure.bodies)
    bodies += fmt::format("{}'{}'", bodies.empty() ? "" : ", ", name);
  for (const FailedAttempt& attempt : failure.tried) {
    tried += fmt::format("{}{} (h = {:g} s): {}", tried.empty() ? "" : "; ", attempt.start,
                         attempt.h, attempt.outcome);
  }
  const bool hull = failure.model == "hull" || failure.model == "auto";
  return fmt::format(
      "{}solver failed at t = {:.6g} s on body {}: residual {:.3g} > tolerance "
      "{:.3g}; tried {}",
      hull ? "" : failure.model + " model: ", failure.t, bodies, failure.residual,
      failure.tolerance, tried);
}

SolverFailure::SolverFailure(StepFailure failure)
    : std::runtime_error(FormatStepFailure(failure)),
      step_failure_(std::make_shared<const StepFailure>(std::move(failure))) {}

}  // namespace ecpsim::engine
