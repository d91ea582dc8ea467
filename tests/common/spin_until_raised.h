#pragma once
// A thread busy until a CancelFlag is raised: what the CPU watchdog's and budget's tests watch.

#include "common/cancel_flag.h"
#include "common/cpu_clock.h"
#include "common/cpu_watchdog.h"

namespace ecpsim::testing {

// s of CPU: how long SpinUntilRaised waits at most before it counts the watchdog as asleep
inline constexpr double kGiveUp = 10;
// s of CPU past a deadline the flag may come: ten of the watchdog's 10 ms reads, for a loaded
// machine whose watchdog thread waits its turn
inline constexpr double kLateness = 10 * CpuWatchdog::kDefaultPeriod;

/// Spins on this thread until `flag` is raised (or kGiveUp): the thread's CPU time when it saw it.
inline double SpinUntilRaised(const CancelFlag& flag) {
  const double start = ThreadCpuSeconds();
  volatile double x = 0;
  while (!flag.raised() && ThreadCpuSeconds() - start < kGiveUp) {
    for (int i = 0; i < 1000; ++i) x = x + i;
  }
  return ThreadCpuSeconds();
}

}  // namespace ecpsim::testing
