// auto against hull in one bench run: the ratio of their CPU per simulated second at each step
// size both completed, its median over the sweep, the largest, and the verdict against
// kMaxAutoOverHull.

#include "evaluation/auto_cost.h"

#include <gtest/gtest.h>

namespace ecpsim::evaluation {
namespace {

// the ratios below are quotients of short decimals: a few ulps
constexpr double kRatioRoundOff = 1e-14;

WorkPrecisionRow Row(const std::string& scenario, const std::string& method, double h,
                     double cpu, bool failed = false) {
  WorkPrecisionRow r;
  r.scenario = scenario;
  r.method = method;
  r.h = h;
  r.cpu_per_sim_s = cpu;
  r.failed = failed;
  return r;
}

TEST(CompareAutoWithHull, TakesTheMedianRatioOverTheStepsBothCompleted) {
  const std::vector<WorkPrecisionRow> rows = {
      Row("slide", "hull", 0.01, 2.0),  Row("slide", "auto", 0.01, 1.0),
      Row("slide", "hull", 0.005, 4.0), Row("slide", "auto", 0.005, 6.0),
      Row("slide", "hull", 0.002, 8.0), Row("slide", "auto", 0.002, 4.0),
      // no hull run at this step, and a failed auto run: neither counts
      Row("slide", "auto", 0.001, 99.0), Row("slide", "hull", 0.0005, 1.0),
      Row("slide", "auto", 0.0005, -1, /*failed=*/true), Row("slide", "ode-coulomb", 0.01, 0.1)};
  const std::vector<AutoCost> costs = CompareAutoWithHull(rows);
  ASSERT_EQ(costs.size(), 1u);
  EXPECT_EQ(costs[0].scenario, "slide");
  EXPECT_EQ(costs[0].steps, 3);
  EXPECT_NEAR(costs[0].median, 0.5, kRatioRoundOff);
  EXPECT_NEAR(costs[0].largest, 1.5, kRatioRoundOff);
  EXPECT_EQ(costs[0].largest_h, 0.005);
  EXPECT_FALSE(costs[0].Dearer());
}

TEST(CompareAutoWithHull, CallsAutoDearerOnlyBeyondTheNoiseOfOneRun) {
  const auto cost = [](double auto_cpu) {
    return CompareAutoWithHull({Row("tbar", "hull", 0.01, 1.0), Row("tbar", "auto", 0.01, auto_cpu),
                                Row("tbar", "hull", 0.02, 2.0),
                                Row("tbar", "auto", 0.02, 2 * auto_cpu)})
        .at(0);
  };
  EXPECT_FALSE(cost(1.05).Dearer());
  EXPECT_FALSE(cost(1.09).Dearer());
  EXPECT_TRUE(cost(1.2).Dearer());
}

TEST(CompareAutoWithHull, LeavesOutScenariosWithoutBothModels) {
  EXPECT_TRUE(CompareAutoWithHull({Row("stack", "hull", 0.01, 1.0),
                                   Row("pyramid", "auto", 0.01, 1.0),
                                   Row("train", "hull", 0.01, 1.0),
                                   Row("train", "auto", 0.01, -1, /*failed=*/true)})
                  .empty());
}

}  // namespace
}  // namespace ecpsim::evaluation
