#pragma once
// What one time step's solve reports, and the error raised when it cannot be solved.

#include <stdexcept>
#include <string>

namespace ecpsim::engine {

struct StepReport {
  bool converged = false;
  int iterations = 0;        // Newton iterations, summed over bodies and sub-steps
  double residual = 0;       // max over bodies of the unscaled residual (see engine/README.md)
  int retries = 0;           // restarts of the ladder used (0 when the warm start converged)
  int substeps = 1;          // 1, 2 or 4
};

/// The step could not be solved after every retry. The message names time, body, residual and
/// what was tried.
class SolverFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ecpsim::engine
