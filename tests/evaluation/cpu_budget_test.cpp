#include "evaluation/cpu_budget.h"

#include <gtest/gtest.h>

#include "common/cpu_clock.h"
#include "tests/common/spin_until_raised.h"

namespace ecpsim::evaluation {
namespace {

using testing::kLateness;
using testing::SpinUntilRaised;

TEST(CpuBudgetTest, AStepThatReachesTheLimitIsStoppedInsideIt) {
  CpuBudget budget(0.05);
  // a quick step: within the budget
  EXPECT_EQ(budget.Charge([] {}), CpuBudget::Outcome::kWithin);
  // a step polling the flag as the solvers do: stopped, and charged what it used
  const auto step = [&] {
    SpinUntilRaised(*budget.flag());
    ThrowIfCancelled(budget.flag(), "the test's step");
  };
  EXPECT_EQ(budget.Charge(step), CpuBudget::Outcome::kStopped);
  EXPECT_GE(budget.used_s(), 0.05);
  EXPECT_LE(budget.used_s(), 0.05 + kLateness);
}

TEST(CpuBudgetTest, AStepThatEndsPastTheLimitSpendsIt) {
  CpuBudget budget(0.02);
  // a step that never looks at the flag (an external engine's): done, and the budget spent
  const auto step = [] {
    volatile double x = 0;
    const double start = ThreadCpuSeconds();
    while (ThreadCpuSeconds() - start < 0.03) x = x + 1;
  };
  EXPECT_EQ(budget.Charge(step), CpuBudget::Outcome::kSpent);
  EXPECT_GE(budget.used_s(), 0.03);
}

}  // namespace
}  // namespace ecpsim::evaluation
