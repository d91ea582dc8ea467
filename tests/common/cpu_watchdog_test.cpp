#include "common/cpu_watchdog.h"

#include <gtest/gtest.h>

#include "common/cpu_clock.h"
#include "tests/common/spin_until_raised.h"

namespace ecpsim {
namespace {

using testing::kLateness;
using testing::SpinUntilRaised;

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
