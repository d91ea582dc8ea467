#pragma once
// A run's CPU-time limit, kept inside its steps: each step is charged its CPU time, and a step
// that would take the run past the limit stops within a solver iteration of it (a CpuWatchdog
// raising the steps' CancelFlag) instead of running on for minutes.

#include <utility>

#include "common/cancel_flag.h"
#include "common/cpu_clock.h"
#include "common/cpu_watchdog.h"

namespace ecpsim::evaluation {

class CpuBudget {
 public:
  /// `limit_s` CPU seconds of the calling thread for the steps charged to it.
  explicit CpuBudget(double limit_s) : limit_s_(limit_s), watchdog_(flag_) {}

  /// What the steps charged to this budget must stop on (engine::StopStepsOn).
  const CancelFlag* flag() const { return &flag_; }

  /// How a charged step ended: within the budget, done but with the budget spent, or stopped
  /// by the limit inside it (it threw Cancelled; what it did is undone).
  enum class Outcome { kWithin, kSpent, kStopped };

  /// Calls `step()` with what is left of the budget as its deadline and charges its CPU time
  /// (also when it throws anything but Cancelled, which it rethrows).
  template <typename Step>
  Outcome Charge(Step&& step) {
    const double start = ThreadCpuSeconds();
    watchdog_.SetDeadline(start + (limit_s_ - used_s_));
    Outcome outcome = Outcome::kWithin;
    try {
      std::forward<Step>(step)();
    } catch (const Cancelled&) {
      outcome = Outcome::kStopped;
    } catch (...) {
      used_s_ += ThreadCpuSeconds() - start;
      throw;
    }
    used_s_ += ThreadCpuSeconds() - start;
    if (outcome == Outcome::kWithin && used_s_ > limit_s_) outcome = Outcome::kSpent;
    return outcome;
  }

  double used_s() const { return used_s_; }

 private:
  double limit_s_;
  double used_s_ = 0;
  CancelFlag flag_;
  CpuWatchdog watchdog_;
};

}  // namespace ecpsim::evaluation
