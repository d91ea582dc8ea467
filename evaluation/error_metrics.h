#pragma once
// How far a run is from its reference: state, position, angle and velocity errors over the
// sample times, the fraction of samples in the wrong contact mode, the stop-time error.

#include "evaluation/trajectory_run.h"

namespace ecpsim::evaluation {

struct TrajectoryErrors {
  double state = 0;  // m, max over samples of |Δp| + length·|Δθ| (the work–precision error)
  double position = 0;    // m, max |Δp|
  double angle = 0;       // rad, max rotation angle between the orientations
  double velocity = 0;    // m/s, max |Δv| + length·|Δω|
  double wrong_mode = 0;  // fraction of samples whose ContactMode differs
  double stop_time = -1;  // s, |t_stop − t_stop,ref| (< 0: either never stops)
};

/// Compares `run` with `reference` at their common sample times (a failed run is compared over
/// the samples it reached). `length` weights angles (m).
TrajectoryErrors CompareTrajectories(const RunRecord& run, const RunRecord& reference,
                                     double length);

}  // namespace ecpsim::evaluation
