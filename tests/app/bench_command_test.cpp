// `ecpsim bench` end to end: a small sweep, shards and their merge, and bad input.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "engine/scene_io/scene_yaml.h"
#include "evaluation/drop_sweep.h"
#include "evaluation/scaling.h"
#include "evaluation/stability_map.h"
#include "evaluation/work_precision.h"
#include "tests/cli_test.h"

namespace ecpsim::testing {
namespace {

namespace fs = std::filesystem;

class BenchCommandTest : public CliTest {
 protected:
  // runs `command` as shards 1/2 and 2/2 into dir_/s1 and dir_/s2, each of which must succeed and
  // must not draw `chart` (it would show a part of the sweep; "" for none), then merges them into
  // dir_/all
  CliResult ShardAndMerge(const std::string& command, const std::string& chart) {
    for (int shard = 1; shard <= 2; ++shard) {
      const fs::path part = dir_ / fmt::format("s{}", shard);
      const CliResult r =
          Run(fmt::format("{} --shard {}/2 -o '{}'", command, shard, part.string()));
      EXPECT_EQ(r.exit_code, 0) << r.output;
      if (!chart.empty()) {
        EXPECT_FALSE(fs::exists(part / chart)) << chart;
      }
    }
    return Run(fmt::format("bench --merge '{}' '{}' -o '{}'", (dir_ / "s1").string(),
                           (dir_ / "s2").string(), (dir_ / "all").string()));
  }

  static std::string ReadText(const fs::path& path) {
    std::ifstream file(path);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
  }
};

// a sweep small enough for CI: two closed-form scenarios, one map, two step sizes
const char* kSmallSweep =
    "bench --methods hull,point --scenarios slide,push_slide --maps impact --steps 0.01,0.002 "
    "--no-drops --no-scaling";
// the drop sweep's smallest useful part: one seed of two kinds and one collection file
const char* kSmallDrops =
    "bench --no-work-precision --no-stability --no-scaling --drop-kinds l_shape,u_shape,file "
    "--drop-seeds 1 --drop-poses 1";
// the scaling benchmark alone, two models on a box and two stacks, one step per timed block,
// two rounds
const char* kSmallScaling =
    "bench --no-work-precision --no-stability --no-drops --methods hull,auto --scaling-sizes "
    "1,4,8 --scaling-steps 1 --scaling-rounds 2";

TEST_F(BenchCommandTest, WritesCsvChartsAndResults) {
  const fs::path out = dir_ / "bench";
  const CliResult r = Run(fmt::format("{} -o '{}'", kSmallSweep, out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* file : {"work_precision.csv", "stability.csv", "work_precision_slide.png",
                           "work_precision_push_slide.png", "stability_impact.png", "results.md"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file << "\n" << r.output;
  }
  const auto rows = evaluation::ReadWorkPrecisionCsv((out / "work_precision.csv").string());
  ASSERT_EQ(rows.size(), 2u * 2 * 2);
  for (const auto& row : rows) {
    EXPECT_FALSE(row.failed) << row.method << " " << row.failure;
    if (row.method == "hull") {
      // the slide's first-order error: μ g h t_stop / 2 = 0.005 m at h = 0.01 (to 1 %)
      constexpr double kOnePercent = 0.005;  // m/s, of error / h = 0.5
      if (row.scenario == "slide") {
        EXPECT_NEAR(row.error_state / row.h, 0.5, kOnePercent);
      }
      constexpr double kPenetration = 1e-9;  // m: the solver's position error, with margin
      EXPECT_LT(row.max_penetration, kPenetration);
    }
  }
  const auto cells = evaluation::ReadStabilityCsv((out / "stability.csv").string());
  EXPECT_EQ(cells.size(), 2u * 2 * evaluation::StabilityMaps("")[0].values.size());
}

// a scenario without a reference (the 24-box bin, run by the peers alone: ecpsim's own run of it
// takes minutes): no error anywhere, its drift at rest in the table and the chart. MuJoCo's
// buffers for the bin's 396 pairs could not be allocated before they were capped per body
TEST_F(BenchCommandTest, AClutterBinIsChartedByItsDriftAtRest) {
  const fs::path out = dir_ / "clutter";
  const CliResult r =
      Run(fmt::format("bench --methods mujoco-default,ode-default --scenarios clutter --steps 0.01 "
                      "--no-stability --no-drops --no-scaling -o '{}'",
                      out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "work_precision_clutter.png")) << r.output;
  const auto rows = evaluation::ReadWorkPrecisionCsv((out / "work_precision.csv").string());
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    EXPECT_FALSE(row.failed) << row.method << " " << row.failure;
    EXPECT_EQ(row.steps, 200) << row.method;
    EXPECT_EQ(row.error_state, -1) << row.method;
    EXPECT_GE(row.drift, 0) << row.method;
  }
  const std::string text = ReadText(out / "results.md");
  EXPECT_TRUE(std::regex_search(text, std::regex(R"(\| mujoco-default \| 0\.01 \| – \|)"))) << text;
  EXPECT_NE(text.find("for the dominoes and the clutter bins, from its place at 1 s"),
            std::string::npos)
      << text;
}

// the peg falling into the hole through a block's four convex parts, stepped by the hull model
// and by MuJoCo given the same parts: each measured against its own converged run, with no
// failure and the whole scene run
TEST_F(BenchCommandTest, APegInHoleRowPerMethodAgainstItsConvergedRun) {
  const fs::path out = dir_ / "peg";
  const double h = 0.01;  // s
  const CliResult r = Run(fmt::format(
      "bench --methods hull,mujoco-coulomb --scenarios peg_in_hole --steps {} --no-stability "
      "--no-drops --no-scaling --no-charts -o '{}'",
      h, out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const engine::Scene scene =
      engine::LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/peg_in_hole.yaml").scene;
  const auto rows = evaluation::ReadWorkPrecisionCsv((out / "work_precision.csv").string());
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    EXPECT_EQ(row.scenario, "peg_in_hole");
    EXPECT_FALSE(row.failed) << row.method << " " << row.failure;
    EXPECT_EQ(row.steps, std::lround(scene.duration / h)) << row.method;
    EXPECT_GT(row.cpu_per_sim_s, 0) << row.method;
    EXPECT_GE(row.error_state, 0) << row.method;
    EXPECT_GE(row.reference_uncertainty, 0) << row.method;
    if (row.method == "hull") {
      // its reference is the hull model's own converged run
      EXPECT_EQ(row.error_vs_hull, row.error_state);
      constexpr double kPenetration = 1e-9;  // m: the solver's position error, with margin
      EXPECT_LT(row.max_penetration, kPenetration);
    }
  }
  const std::string text = ReadText(out / "results.md");
  EXPECT_TRUE(std::regex_search(text, std::regex(R"(\| mujoco-coulomb \| 0\.01 \| \d)"))) << text;
}

// the auto-against-hull check's line and table (its verdict is a timing's, not asserted here)
TEST_F(BenchCommandTest, ComparesAutoWithHullInTheSameRun) {
  const fs::path out = dir_ / "auto";
  const CliResult r = Run(fmt::format(
      "bench --methods hull,auto,point --scenarios slide --steps 0.01,0.005 --no-stability "
      "--no-drops --no-scaling --no-charts -o '{}'",
      out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("auto against hull (median CPU ratio over the step sizes, dearer above "
                          "1.1): "),
            std::string::npos)
      << r.output;
  const std::string text = ReadText(out / "results.md");
  EXPECT_NE(text.find("### auto against hull"), std::string::npos) << text;
  EXPECT_TRUE(std::regex_search(text, std::regex(R"(\| slide \| 2 \| \d+\.\d\d \|)"))) << text;
}

TEST_F(BenchCommandTest, ShardsMergeIntoTheWholeSweep) {
  const CliResult merged = ShardAndMerge(kSmallSweep, "work_precision_slide.png");
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(evaluation::ReadWorkPrecisionCsv((dir_ / "all" / "work_precision.csv").string()).size(),
            8u);
  EXPECT_TRUE(fs::exists(dir_ / "all" / "stability_impact.png"));
  EXPECT_NE(merged.output.find("merged 8 work-precision rows"), std::string::npos) << merged.output;
}

TEST_F(BenchCommandTest, DropSweepShardsMergeIntoOneTable) {
  // a closed tetrahedron is the collection
  fs::create_directories(dir_ / "meshes");
  std::ofstream(dir_ / "meshes" / "tetra.obj")
      << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const CliResult merged = ShardAndMerge(
      fmt::format("{} --drop-meshes '{}'", kSmallDrops, (dir_ / "meshes").string()), "");
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  // 2 kinds × 1 seed + 1 file × 1 pose, each at the fixed and the scaled step
  const auto rows = evaluation::ReadDropSweepCsv((dir_ / "all" / "drop_sweep.csv").string());
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(evaluation::DropCaseKey(rows.front().Case()), "l_shape:0");
  EXPECT_EQ(rows.back().kind, evaluation::kFileKind);
  const std::string text = ReadText(dir_ / "all" / "results.md");
  EXPECT_NE(text.find("## Drop sweep"), std::string::npos) << text;
  EXPECT_NE(text.find("| u_shape | scaled | 1 |"), std::string::npos) << text;
}

TEST_F(BenchCommandTest, ScalingWritesItsTableChartAndSection) {
  const fs::path out = dir_ / "scaling";
  const CliResult r = Run(fmt::format("{} -o '{}'", kSmallScaling, out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "scaling.png")) << r.output;
  const auto rows = evaluation::ReadScalingCsv((out / "scaling.csv").string());
  ASSERT_EQ(rows.size(), 2u * 3);
  for (const auto& row : rows) {
    EXPECT_FALSE(row.failed) << row.method << " " << row.bodies << ": " << row.failure;
    EXPECT_GT(row.cpu_per_step, 0);
  }
  const std::string text = ReadText(out / "results.md");
  EXPECT_NE(text.find("## Scaling: cost per step against the number of bodies"), std::string::npos)
      << text;
  // N = 4 and 8 are two sizes from the first whole stack: each method has a slope
  EXPECT_NE(text.find("| method | N = 1 | N = 4 | N = 8 | slope |"), std::string::npos) << text;
  for (const char* method : {"hull", "auto"}) {
    const std::regex with_slope(fmt::format(R"(\| {} \|( [^|]+ \|){{3}} -?\d+\.\d\d \|)", method));
    EXPECT_TRUE(std::regex_search(text, with_slope)) << method << "\n" << text;
    EXPECT_NE(r.output.find(fmt::format("scaling {}: slope ", method)), std::string::npos)
        << r.output;
  }
}

TEST_F(BenchCommandTest, ScalingShardsMerge) {
  const CliResult merged = ShardAndMerge(kSmallScaling, "scaling.png");
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(evaluation::ReadScalingCsv((dir_ / "all" / "scaling.csv").string()).size(), 6u);
  EXPECT_TRUE(fs::exists(dir_ / "all" / "scaling.png"));
  EXPECT_NE(merged.output.find("merged 6 scaling rows"), std::string::npos) << merged.output;
}

TEST_F(BenchCommandTest, BadInputIsNamed) {
  CliResult r = Run("bench --shard 3/2 -o " + (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--shard '3/2': expected i/N"), std::string::npos) << r.output;
  r = Run("bench --methods hull,nosuch -o " + (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--methods 'nosuch': expected one of hull"), std::string::npos)
      << r.output;
  r = Run("bench --steps 0.003 --scenarios slide --methods hull --no-stability -o " +
          (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("does not divide the sample interval"), std::string::npos) << r.output;
  r = Run("bench --no-work-precision --no-stability --drop-case nosuch:1 -o " +
          (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("'nosuch' is neither a mesh kind nor a file"), std::string::npos)
      << r.output;
  r = Run("bench --no-work-precision --no-stability --drop-kinds cube -o " + (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("drop sweep kind 'cube': expected one of convex"), std::string::npos)
      << r.output;
  r = Run("bench --no-work-precision --no-stability --no-drops --scaling-sizes 8,0 -o " +
          (dir_ / "never").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--scaling-sizes = 0: expected an integer in [1, 10000]"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "never")) << r.output;
  r = Run("bench --merge " + dir_.string() + " -o " + (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("neither work_precision.csv nor stability.csv"), std::string::npos)
      << r.output;
}

// every option is checked before any work: a bad stability map or drop kind used to be found
// only after the work-precision sweep (minutes in a full run) had run and written its table
TEST_F(BenchCommandTest, ABadLaterOptionStopsTheRunBeforeAnyWork) {
  const fs::path out = dir_ / "never";
  const std::string small = "bench --methods hull --scenarios slide --steps 0.01 ";
  CliResult r = Run(small + "--maps nosuch --no-drops -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--maps 'nosuch': expected one of impact"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out)) << r.output;
  r = Run(small + "--no-stability --drop-kinds cube -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("drop sweep kind 'cube'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << r.output;
  r = Run(small + "--no-stability --drop-steps sometimes -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--drop-steps 'sometimes'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << r.output;
}

}  // namespace
}  // namespace ecpsim::testing
