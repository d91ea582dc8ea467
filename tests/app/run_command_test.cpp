// Runs the built `ecpsim` binary (run and drop) and checks its files: trajectory.csv and
// summary.json.

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/report/trajectory_columns.h"
#include "tests/app/run_fixture.h"

namespace ecpsim {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// the slide's deceleration μ g (m/s²) and its closed-form velocity; implicit Euler with a
// constant deceleration reproduces v(t) = v0 − μ g t to round-off, and the solver's tolerance
// (1e-12 on the residual) bounds the error far below 1e-8 m/s
constexpr double kMuG = 0.22 * 9.8;
constexpr double kVelocityTolerance = 1e-8;  // m/s
constexpr double kWeight = 15 * 9.8;         // N, the slide's box
// relative: impulse / h in floating point against the column's value (a few roundings)
constexpr double kForceRoundOff = 1e-14;
// relative: the step's force balance holds to the solver's tolerance (1e-12, relative to the
// body's own impulse scale) with margin for the scaled residual's conversion
constexpr double kForceTolerance = 1e-9;
// s: a row's t, k steps of h, to round-off
constexpr double kTimeRoundOff = 1e-12;
// m: a body resting on the ground, to the solver's position error (1e-12 of its lengths) with
// margin
constexpr double kPositionTolerance = 1e-9;

class RunCommandTest : public testing::RunFixture {
 protected:
  static std::vector<std::vector<std::string>> ReadCsv(const fs::path& path) {
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
      std::vector<std::string> fields;
      std::stringstream stream(line);
      for (std::string field; std::getline(stream, field, ',');) fields.push_back(field);
      rows.push_back(fields);
    }
    return rows;
  }

  // every data field parses completely as a finite double, but the model columns' (text)
  static void ExpectAllFinite(const std::vector<std::vector<std::string>>& rows) {
    for (size_t r = 1; r < rows.size(); ++r) {
      ASSERT_EQ(rows[r].size(), rows[0].size()) << "row " << r;
      for (size_t c = 0; c < rows[r].size(); ++c) {
        if (engine::IsModelColumn(rows[0][c])) continue;
        const std::string& field = rows[r][c];
        size_t used = 0;
        const double value = std::stod(field, &used);
        EXPECT_EQ(used, field.size()) << field;
        EXPECT_TRUE(std::isfinite(value)) << field;
      }
    }
  }
};

TEST_F(RunCommandTest, SlideWritesTheTrajectoryAndSummary) {
  const fs::path out = dir_ / "slide";
  const testing::CliResult result =
      Run(fmt::format("run '{}/scenes/slide.yaml' -o '{}'", ECPSIM_SOURCE_DIR, out.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;

  const auto rows = ReadCsv(out / "trajectory.csv");
  EXPECT_THAT(Leftovers(out), ::testing::IsEmpty());
  // one body and one contact: no name prefixes
  const std::vector<std::string> expected = {
      "t",  "px", "py",    "pz",  "qw",  "qx",  "qy",  "qz",    "vx",       "vy",   "vz",
      "wx", "wy", "wz",    "a1x", "a1y", "a1z", "a2x", "a2y",   "a2z",      "pn",   "pt",
      "po", "pr", "sigma", "fn",  "ft",  "fo",  "fr",  "iters", "residual", "model"};
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], expected);
  // 0.5 s / 0.01 s = 50 steps plus the initial state
  ASSERT_EQ(rows.size(), 1u + 51u);
  ExpectAllFinite(rows);
  // model: auto (the default) slides the flat box with the planar model, every step
  EXPECT_EQ(rows[1].back(), "initial");
  for (size_t r = 2; r < rows.size(); ++r) EXPECT_EQ(rows[r].back(), "planar") << "row " << r;

  // the closed form: v(t) = max(0, v0 − μ g t), the box stays flat at pz = 0.05 m
  for (size_t r = 1; r < rows.size(); ++r) {
    const double t = std::stod(rows[r][0]);
    EXPECT_NEAR(t, 0.01 * (r - 1), kTimeRoundOff);
    EXPECT_NEAR(std::stod(rows[r][8]), std::max(0.0, 0.5 - kMuG * t), kVelocityTolerance)
        << "t = " << t;
    EXPECT_NEAR(std::stod(rows[r][3]), 0.05, kPositionTolerance) << "t = " << t;
    // the forces are the step's impulses over h; flat on the ground the normal force is m g
    // (the vertical velocity stays 0), and while sliding the friction force is μ m g
    const double pn = std::stod(rows[r][20]), pt = std::stod(rows[r][21]);
    const double fn = std::stod(rows[r][25]), ft = std::stod(rows[r][26]);
    if (r == 1) continue;  // the initial state: no step, no impulse
    EXPECT_NEAR(fn, pn / 0.01, kForceRoundOff * kWeight) << "t = " << t;
    EXPECT_NEAR(ft, pt / 0.01, kForceRoundOff * kWeight) << "t = " << t;
    EXPECT_NEAR(fn, kWeight, kForceTolerance * kWeight) << "t = " << t;
    if (t < 0.23) {
      EXPECT_NEAR(std::abs(ft), 0.22 * kWeight, kForceTolerance * kWeight) << t;
    }
  }

  const nlohmann::json summary = ReadJson(out / "summary.json");
  for (const char* key :
       {"steps", "failures", "retries", "iterations_mean", "iterations_max", "max_penetration",
        "wall_s", "median_step_us", "scene", "h", "duration", "converged"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_EQ(summary["steps"], 50);
  EXPECT_EQ(summary["models"], nlohmann::json({{"planar", 50}}));
  EXPECT_EQ(summary["failures"], 0);
  EXPECT_EQ(summary["converged"], true);
  EXPECT_EQ(summary["h"], 0.01);
  EXPECT_EQ(summary["duration"], 0.5);
  EXPECT_FALSE(summary.contains("error"));
  // resting on its face: no vertex below the ground beyond the solver's position error
  EXPECT_GE(summary["max_penetration"].get<double>(), 0);
  EXPECT_LT(summary["max_penetration"].get<double>(), kPositionTolerance);
  // the mean of per-step counts lies between 0 and their maximum
  EXPECT_GE(summary["iterations_mean"].get<double>(), 0);
  EXPECT_LE(summary["iterations_mean"].get<double>(), summary["iterations_max"].get<double>());
}

TEST_F(RunCommandTest, OverridesChangeStepAndOutputCadence) {
  const fs::path out = dir_ / "coarse";
  const testing::CliResult result =
      Run(fmt::format("run '{}/scenes/slide.yaml' -o '{}' --dt 0.02 --set "
                      "output.every=10 --set bodies.0.velocity=[0.25,0,0]",
                      ECPSIM_SOURCE_DIR, out.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto rows = ReadCsv(out / "trajectory.csv");
  // 25 steps of 0.02 s; rows at steps 0, 10, 20 and the last, 25
  ASSERT_EQ(rows.size(), 1u + 4u);
  EXPECT_NEAR(std::stod(rows[2][0]), 0.2, kTimeRoundOff);
  EXPECT_NEAR(std::stod(rows[4][0]), 0.5, kTimeRoundOff);
  // v0 = 0.25 m/s stops at 0.25 / (μ g) ≈ 0.116 s: at rest in every later row
  EXPECT_NEAR(std::stod(rows[2][8]), 0, kVelocityTolerance);
  EXPECT_EQ(ReadJson(out / "summary.json")["steps"], 25);
}

TEST_F(RunCommandTest, BadSceneExitsWithOneAndALocatedMessage) {
  std::ofstream(dir_ / "bad.yaml") << "duration: 1\nbodies:\n  - shape: {sphere: {radius: 1}}\n"
                                      "    mass: -2\n    position: [0, 0, 1]\n";
  const testing::CliResult result =
      Run(fmt::format("run '{}' -o '{}'", (dir_ / "bad.yaml").string(), (dir_ / "o").string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_THAT(result.output,
              HasSubstr("bad.yaml:4:11: bodies[0].mass = -2: expected a finite mass > 0 kg"));
  EXPECT_FALSE(fs::exists(dir_ / "o" / "summary.json"));
}

TEST_F(RunCommandTest, SolverFailureExitsWithThreeAndLeavesValidFiles) {
  // one Newton iteration cannot solve the first contact step from a cold start
  const fs::path out = dir_ / "fail";
  const testing::CliResult result =
      Run(fmt::format("run '{}/scenes/tilted_box.yaml' -o '{}' --set "
                      "solver.max_iterations=1",
                      ECPSIM_SOURCE_DIR, out.string()));
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_THAT(result.output, HasSubstr("solver failure"));
  EXPECT_THAT(Leftovers(out), ::testing::IsEmpty());
  const auto rows = ReadCsv(out / "trajectory.csv");
  const nlohmann::json summary = ReadJson(out / "summary.json");
  EXPECT_EQ(summary["failures"], 1);
  EXPECT_EQ(summary["converged"], false);
  EXPECT_FALSE(summary["error"].get<std::string>().empty());
  // the rows written before the failure: the initial state and every completed step
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows.size(), 2u + summary["steps"].get<size_t>());
  ExpectAllFinite(rows);
}

TEST_F(RunCommandTest, DropLandsAMeshOnTheGround) {
  // the fixture box [0,1]×[0,2]×[0,3] m (6000 kg at 1000 kg/m³), dropped from 0.05 m flat
  const fs::path out = dir_ / "drop";
  const testing::CliResult result =
      Run(fmt::format("drop '{}/tests/fixtures/meshes/box.obj' -o '{}' --height 0.05 "
                      "--duration 0.3",
                      ECPSIM_SOURCE_DIR, out.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto rows = ReadCsv(out / "trajectory.csv");
  ASSERT_EQ(rows.size(), 1u + 31u);
  ExpectAllFinite(rows);
  // starts with its CM 1.5 m + 0.05 m up; free fall lasts sqrt(2 · 0.05 / g) ≈ 0.10 s, and the
  // box ends resting on its face at pz = 1.5 m
  constexpr double kPlacedRoundOff = 1e-12;  // m: 1.5 + 0.05
  // m: after the 6 t box's landing impact, far below its 5 cm fall
  constexpr double kLandedTolerance = 1e-6;
  EXPECT_NEAR(std::stod(rows[1][3]), 1.55, kPlacedRoundOff);
  EXPECT_NEAR(std::stod(rows.back()[3]), 1.5, kLandedTolerance);
  EXPECT_LT(ReadJson(out / "summary.json")["max_penetration"].get<double>(), kLandedTolerance);
}

TEST_F(RunCommandTest, AFifoOrSymlinkAtAnOutputIsRefusedBeforeTheRunAndLeftAlone) {
  // a reader blocked on a FIFO, or a symlink pointing elsewhere, must not be replaced by a file
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  ASSERT_EQ(::mkfifo((out / "summary.json").c_str(), 0600), 0);
  testing::CliResult result = Run(fmt::format("run scenes/slide.yaml -o '{}'", out.string()));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("summary.json: a FIFO (named pipe) is there; expected a "
                                       "regular file or nothing"));
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(out / "summary.json")));
  EXPECT_FALSE(fs::exists(out / "trajectory.csv"));

  fs::remove(out / "summary.json");
  std::ofstream(dir_ / "elsewhere.csv") << "keep\n";
  fs::create_symlink(dir_ / "elsewhere.csv", out / "trajectory.csv");
  result = Run(fmt::format("run scenes/slide.yaml -o '{}'", out.string()));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("trajectory.csv: a symbolic link (to "));
  EXPECT_TRUE(fs::is_symlink(out / "trajectory.csv"));
  std::ifstream kept(dir_ / "elsewhere.csv");
  std::string line;
  std::getline(kept, line);
  EXPECT_EQ(line, "keep");
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  // nothing else is left in the folder: no temporary files
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
}

TEST_F(RunCommandTest, NumericOptionsAreCheckedBeforeAnyWork) {
  const std::string slide = fmt::format("'{}/scenes/slide.yaml'", ECPSIM_SOURCE_DIR);
  const std::string out = (dir_ / "o").string();
  for (const auto& [options, message] : std::vector<std::pair<std::string, std::string>>{
           {"--dt nan", "--dt = nan: expected a finite time > 0 s"},
           {"--dt 1e-300", "--dt = 1e-300: expected a time in [1e-150, 1e+150] s"},
           {"--duration 1e20",
            "--set duration=1e+20: duration = 1e+20: expected at most 4503599627370496 steps per "
            "run"},
           {"--fps -1", "--fps = -1: expected a finite value > 0"},
           {"--width 100000", "--width = 100000: expected an integer in [16, 8192]"}}) {
    const testing::CliResult result = Run(fmt::format("run {} -o '{}' {}", slide, out, options));
    EXPECT_EQ(result.exit_code, 1) << options << ": " << result.output;
    EXPECT_THAT(result.output, HasSubstr(message)) << options;
  }
  EXPECT_FALSE(fs::exists(dir_ / "o" / "summary.json"));
}

TEST_F(RunCommandTest, InitialPenetrationIsABadInputNamingThePosition) {
  const testing::CliResult result =
      Run(fmt::format("run '{}/scenes/slide.yaml' -o '{}' --set 'bodies.0.position=[0, 0, -0.35]'",
                      ECPSIM_SOURCE_DIR, (dir_ / "o").string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_THAT(result.output,
              HasSubstr("slide.yaml: --set bodies.0.position=[0, 0, -0.35]: bodies[0].position = "
                        "[0, 0, -0.35]: expected an initial pose of body \"box\" whose mesh stays "
                        "out of obstacle \"ground\": a vertex is 0.4 m inside"));
}

TEST_F(RunCommandTest, DropWarnsAboutAMeshInTheWrongUnit) {
  const std::string box = fmt::format("{}/tests/fixtures/meshes/box.obj", ECPSIM_SOURCE_DIR);
  // the 1 × 2 × 3 box declared in millimetres: 3.74 mm across, plausible, no warning
  testing::CliResult result =
      Run(fmt::format("drop '{}' -o '{}' --units mm --duration 0.02", box, (dir_ / "a").string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, ::testing::Not(HasSubstr("warning")));
  // scaled to 374 m: a warning on stderr, and the run goes on
  result =
      Run(fmt::format("drop '{}' -o '{}' --scale 100 --duration 0.02", box, (dir_ / "b").string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr(fmt::format("ecpsim: warning: {} is 374 m across; if it "
                                                   "is in metres use --units m (or --scale 1)",
                                                   box)));
  result = Run(fmt::format("drop '{}' -o '{}' --units yd", box, (dir_ / "c").string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_THAT(result.output, HasSubstr("--units = yd: expected one of mm, cm, m, in"));
}

TEST_F(RunCommandTest, DeskRunsWithThePointModel) {
  const testing::CliResult result =
      Run(fmt::format("run '{}/scenes/desk.yaml' -o '{}' --model point --duration 0.5",
                      ECPSIM_SOURCE_DIR, (dir_ / "out").string()));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, ::testing::Not(::testing::HasSubstr("failed")));
}

}  // namespace
}  // namespace ecpsim
