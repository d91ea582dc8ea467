#pragma once
// Ctrl-C (SIGINT) and SIGTERM during `ecpsim run` and `ecpsim drop`: the run stops the step in
// progress, leaving it undone, and writes complete, consistent outputs instead of dying halfway
// through a file.

#include <stdexcept>
#include <string>

#include "common/cancel_flag.h"

namespace ecpsim::app {

/// While an InterruptGuard lives, SIGINT and SIGTERM only record that they arrived
/// (InterruptSignal()) and raise InterruptFlag(); the run loop asks between steps, and a step in
/// progress stops within a solver iteration (engine::StopStepsOn) with the state as it was. Signals
/// ignored when the guard is made (a background job of a non-interactive shell, nohup) stay
/// ignored. Once one signal has arrived, more are ignored: the outputs being finished take
/// milliseconds (plus the encoder's flush of a video), and stopping in the middle would leave them
/// inconsistent (SIGKILL still stops the process, leaving temporary files that the next run
/// removes: PrepareOutputFolder). The destructor puts back the handlers there were before. One
/// guard at a time.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

/// The first signal (SIGINT or SIGTERM) that arrived under the current InterruptGuard, 0 if none.
int InterruptSignal();

/// Raised with InterruptSignal() becoming non-zero; cleared by each InterruptGuard made.
const CancelFlag& InterruptFlag();

/// "SIGINT", "SIGTERM", else "signal N".
std::string SignalName(int signal);

/// Thrown once an interrupted run has written its outputs; main() prints the message and exits
/// with exit_code(): 128 + the signal's number, the shells' convention (130 for SIGINT, 143 for
/// SIGTERM).
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& message)
      : std::runtime_error(message), signal_(signal) {}
  int exit_code() const { return 128 + signal_; }

 private:
  int signal_;
};

}  // namespace ecpsim::app
