#include "common/cpu_watchdog.h"

#include <gtest/gtest.h>

#include "common/cpu_clock.h"

namespace ecpsim {
namespace {

// s of CPU: what the spins below wait for at most before they count the watchdog as asleep
constexpr double kGiveUp = 10;
// s of CPU past the deadline the flag may come: ten of the watchdog's 10 ms reads, for a loaded
// machine whose watchdog thread waits its turn
constexpr double kLateness = 10 * CpuWatchdog::kDefaultPeriod;

// spins on this thread until `flag` is raised (or kGiveUp): the CPU time when it was seen
double SpinUntilRaised(const CancelFlag& flag) {
  const double start = ThreadCpuSeconds();
  volatile double x = 0;
  while (!flag.raised() && ThreadCpuSeconds() - start < kGiveUp) {
    for (int i = 0; i < 1000; ++i) x = x + i;
  }
  return ThreadCpuSeconds();
}

TEST(CpuWatchdogTest, RaisesTheFlagOnceTheWatchedThreadPassesItsDeadline) {
  CancelFlag flag;
  CpuWatchdog watchdog(flag);
  const double deadline = ThreadCpuSeconds() + 0.05;
  watchdog.SetDeadline(deadline);
  const double seen = SpinUntilRaised(flag);
  ASSERT_TRUE(flag.raised());
  EXPECT_GE(seen, deadline);
  EXPECT_LE(seen, deadline + kLateness);
}

TEST(CpuWatchdogTest, NoDeadlineNoFlag) {
  CancelFlag flag;
  {
    CpuWatchdog watchdog(flag);
    volatile double x = 0;
    const double start = ThreadCpuSeconds();
    while (ThreadCpuSeconds() - start < 0.05) x = x + 1;
  }
  EXPECT_FALSE(flag.raised());
}

}  // namespace
}  // namespace ecpsim
