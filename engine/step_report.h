#pragma once
// What one time step's solve reports, and the errors raised when it cannot be solved.

#include <stdexcept>
#include <string>
#include <vector>

namespace ecpsim::engine {

/// What solved a body's step (trajectory.csv's `model` column, summary.json's counts), from the
/// cheapest: closed-form free flight, the planar sliding model, the hull MNCP, the multi-patch
/// and point models; a kinematic body's motion is prescribed.
enum class StepModel { kFree, kPlanar, kHull, kMultiPatch, kPoint, kKinematic };
/// "free", "planar", "hull", "multipatch", "point", "kinematic".
const char* StepModelName(StepModel model);
inline constexpr int kNumStepModels = 6;

struct StepReport {
  bool converged = false;
  int iterations = 0;        // Newton iterations, summed over bodies and sub-steps
  double residual = 0;       // max over bodies of the unscaled residual (see engine/README.md)
  int retries = 0;           // restarts of the ladder used (0 when the warm start converged)
  int substeps = 1;          // 1, 2, 4 or 16
  // per body of the scene: what solved its step (of its sub-steps, the dearest); empty for a
  // state no step produced (the initial one)
  std::vector<StepModel> models;
};

/// The step could not be solved after every retry. The message names time, body, residual and
/// what was tried.
class SolverFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The scene's contact model does not apply to the scene or stopped applying during the run (the
/// planar model's body is not flat or would tip; an obstacle a model cannot handle). The message
/// names time or body and the violated condition.
class ModelInvalid : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ecpsim::engine
