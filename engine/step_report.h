#pragma once
// What one time step's solve reports, and the errors raised when it cannot be solved.

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace ecpsim::engine {

/// What solved a body's step (trajectory.csv's `model` column, summary.json's counts), from the
/// cheapest: closed-form free flight, the planar sliding model, the hull MNCP, the multi-patch
/// and point models; a kinematic body's motion is prescribed.
/// kParts: the hull model, the body touching through its convex parts (Body::parts) within the
/// step (engine/README.md, "Bodies made of convex parts").
enum class StepModel { kFree, kPlanar, kHull, kMultiPatch, kPoint, kKinematic, kParts };
/// "free", "planar", "hull", "multipatch", "point", "kinematic", "parts".
const char* StepModelName(StepModel model);
inline constexpr int kNumStepModels = 7;

struct StepReport {
  bool converged = false;
  int iterations = 0;   // Newton iterations, summed over bodies and sub-steps
  double residual = 0;  // max over bodies of the unscaled residual (see engine/README.md)
  int retries = 0;      // restarts of the ladder used (0 when the warm start converged)
  int substeps = 1;     // the finest split's: 1, 2, 4, 8 or 16 sub-steps of h
  // islands that slept (replayed their last step, engine/README.md "Sleeping islands") and their
  // bodies
  int sleeping_islands = 0;
  int sleeping_bodies = 0;
  // per body of the scene: what solved its step (of its sub-steps, the dearest); empty for a
  // state no step produced (the initial one)
  std::vector<StepModel> models;
};

/// One attempt of a step that failed: the start it came from, its step length and how it ended.
struct FailedAttempt {
  std::string start;    // what was tried: "warm start", "sliding guess (projected)", "Lemke", ...
  double h = 0;         // s, the attempt's step length
  std::string outcome;  // how it ended: "residual 2.1e-09 after 60 iterations", ...
};

/// A step that could not be solved after every retry: the scene's contact model, the time, the
/// island's bodies, the last residual against the tolerance, and every attempt in order.
struct StepFailure {
  std::string model;  // ContactModelName of the scene's model
  double t = 0;       // s, the start of the step
  std::vector<std::string> bodies;
  double residual = 0;
  double tolerance = 0;
  std::vector<FailedAttempt> tried;
};

/// The one line SolverFailure says of `failure`: "[<model> model: ]solver failed at t = … s on
/// body '…', '…': residual … > tolerance …; tried <start> (h = … s): <outcome>; …"; the hull
/// model's own failures (models "hull" and "auto") carry no model prefix.
std::string FormatStepFailure(const StepFailure& failure);

/// The step could not be solved (StepIslands' record), or a solved state cannot be used (a peer
/// engine's, an output that is not finite: the message alone). The message names time, body and
/// residual, and what was tried.
class SolverFailure : public std::runtime_error {
 public:
  explicit SolverFailure(const std::string& message) : std::runtime_error(message) {}
  explicit SolverFailure(StepFailure failure);
  /// The failed step's record; null for a failure that is no step's.
  const StepFailure* step_failure() const { return step_failure_.get(); }

 private:
  std::shared_ptr<const StepFailure> step_failure_;
};

/// The scene's contact model does not apply to the scene or stopped applying during the run (the
/// planar model's body is not flat or would tip; an obstacle a model cannot handle). The message
/// names time or body and the violated condition.
class ModelInvalid : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ecpsim::engine
