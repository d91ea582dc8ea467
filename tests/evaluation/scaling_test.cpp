// The scaling benchmark on a small grid: a row for every method that applies, each with finite
// positive times and memory; shards that split it; the slope fit over its rows; its CSV.

#include "evaluation/scaling.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "common/atomic_file.h"

namespace ecpsim::evaluation {
namespace {

// one box and two stacks, a few steps, two rounds: the protocol whole, in well under a second
// per method
ScalingOptions SmallRun() {
  ScalingOptions options;
  options.sizes = {1, 8};
  options.warmup_steps = 1;
  options.repeats = 2;
  options.steps_per_repeat = 2;
  options.rounds = 2;
  return options;
}

std::vector<Method> MethodsThatApply() {
  std::vector<Method> methods;
  for (const Method& m : AllMethods()) {
    if (AppliesToStackGrid(m)) methods.push_back(m);
  }
  return methods;
}

TEST(Scaling, PlanarAndMultipatchDoNotApply) {
  EXPECT_FALSE(AppliesToStackGrid(FindMethod("planar")));
  EXPECT_FALSE(AppliesToStackGrid(FindMethod("multipatch")));
  EXPECT_TRUE(AppliesToStackGrid(FindMethod("hull")));
  EXPECT_TRUE(AppliesToStackGrid(FindMethod("auto")));
  EXPECT_FALSE(AppliesToStackGrid(FindMethod("auto-least-energy")));
}

TEST(Scaling, EveryMethodHasARowPerSizeWithFinitePositiveTimes) {
  const ScalingOptions options = SmallRun();
  const std::vector<ScalingRow> rows = RunScaling(AllMethods(), options);
  const std::vector<Method> methods = MethodsThatApply();
  ASSERT_EQ(rows.size(), methods.size() * options.sizes.size());
  // K = warm-up + timed steps, then K more
  const long k = options.warmup_steps + options.repeats * options.steps_per_repeat;
  for (size_t i = 0; i < rows.size(); ++i) {
    const ScalingRow& r = rows[i];
    EXPECT_EQ(r.method, methods[i / options.sizes.size()].name);
    EXPECT_EQ(r.bodies, options.sizes[i % options.sizes.size()]);
    ASSERT_FALSE(r.failed) << r.method << " " << r.bodies << ": " << r.failure;
    EXPECT_EQ(r.steps, 2 * k);
    EXPECT_EQ(r.repeats, options.repeats);
    EXPECT_EQ(r.rounds, options.rounds);
    EXPECT_EQ(r.timed_steps, options.repeats * options.steps_per_repeat);
    for (double t : {r.cpu_per_step, r.wall_per_step}) {
      EXPECT_TRUE(std::isfinite(t) && t > 0) << r.method << " " << r.bodies << ": " << t;
    }
    EXPECT_GT(r.rss_start_mib, 0);
    EXPECT_GE(r.rss_k_mib, 0);
    EXPECT_GE(r.rss_2k_mib, 0);
    // the peak holds every resident set the process had
    EXPECT_GE(r.rss_peak_mib, std::max({r.rss_start_mib, r.rss_k_mib, r.rss_2k_mib}));
  }
}

TEST(Scaling, ARunPastTheCpuLimitIsAFailedRowWithoutTimes) {
  // any step takes more CPU than a nanosecond: the first one ends the run
  constexpr double kNoCpu = 1e-9;  // s
  ScalingOptions options = SmallRun();
  options.sizes = {4};
  options.cpu_limit_s = kNoCpu;
  const std::vector<ScalingRow> rows = RunScaling({FindMethod("hull")}, options);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_TRUE(rows[0].failed);
  EXPECT_EQ(rows[0].steps, 1);
  EXPECT_EQ(rows[0].failure, "CPU limit of 1e-09 s reached after 1 steps");
  EXPECT_EQ(rows[0].cpu_per_step, -1);
  EXPECT_EQ(rows[0].wall_per_step, -1);
  // the memory read when it failed
  EXPECT_GT(rows[0].rss_peak_mib, 0);
}

TEST(Scaling, ShardsSplitTheGroups) {
  ScalingOptions options = SmallRun();
  options.steps_per_repeat = 1;
  const std::vector<Method> methods = {FindMethod("hull"), FindMethod("auto")};
  std::set<std::pair<std::string, long>> seen;
  for (int shard = 1; shard <= 3; ++shard) {
    options.shard_index = shard;
    options.shard_count = 3;
    for (const ScalingRow& r : RunScaling(methods, options)) {
      EXPECT_TRUE(seen.insert({r.method, r.bodies}).second) << r.method << " " << r.bodies;
    }
  }
  EXPECT_EQ(seen.size(), 4u);
}

TEST(Scaling, TheFitStartsAtTheFirstWholeStack) {
  // cost 2 µs per body from the first stack on, and a lone box far off that line
  constexpr double kFitRoundOff = 1e-12;  // of the exponent, as in power_law_fit_test.cpp
  std::vector<ScalingRow> rows;
  for (long n : {1L, 4L, 16L, 64L}) {
    ScalingRow r;
    r.method = "hull";
    r.bodies = n;
    r.cpu_per_step = n == 1 ? 1e-3 : 2e-6 * n;
    r.wall_per_step = n == 1 ? 1e-3 : 3e-6 * n * n;
    rows.push_back(r);
  }
  ScalingRow failed = rows.back();
  failed.bodies = 1000;
  failed.failed = true;
  rows.push_back(failed);
  const auto cpu = FitScaling(rows, "hull", false);
  const auto wall = FitScaling(rows, "hull", true);
  ASSERT_TRUE(cpu && wall);
  EXPECT_EQ(cpu->points, 3);
  EXPECT_NEAR(cpu->exponent, 1, kFitRoundOff);
  EXPECT_NEAR(wall->exponent, 2, kFitRoundOff);
  EXPECT_FALSE(FitScaling(rows, "auto", false));
}

TEST(Scaling, CsvReadsBackWhatItWrote) {
  ScalingRow r;
  r.method = "mujoco-coulomb";
  r.bodies = 250;
  r.steps = 110;
  r.repeats = 5;
  r.timed_steps = 50;
  r.rounds = 3;
  r.failed = true;
  r.cpu_per_step = 1.25e-3;
  r.rss_peak_mib = 42.5;
  r.failure = "CPU limit of 300 s reached after 7 steps";
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "scaling_test.csv";
  WriteFileAtomically(path.string(), ScalingCsv({r}));
  const std::vector<ScalingRow> back = ReadScalingCsv(path.string());
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].method, r.method);
  EXPECT_EQ(back[0].bodies, r.bodies);
  EXPECT_EQ(back[0].steps, r.steps);
  EXPECT_EQ(back[0].repeats, r.repeats);
  EXPECT_EQ(back[0].timed_steps, r.timed_steps);
  EXPECT_EQ(back[0].rounds, r.rounds);
  EXPECT_TRUE(back[0].failed);
  EXPECT_EQ(back[0].cpu_per_step, r.cpu_per_step);
  EXPECT_EQ(back[0].wall_per_step, -1);
  EXPECT_EQ(back[0].rss_peak_mib, r.rss_peak_mib);
  EXPECT_EQ(back[0].failure, r.failure);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ecpsim::evaluation
