// The trajectory does not depend on what else a run writes: `ecpsim run` with frames, a video, a
// frame rate, a frame size or a row interval gives byte-identical trajectory.csv rows.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "tests/cli_test.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;

// the T-bar lies flat, tilts onto a hull edge and rocks: before frames stopped moving the
// engine's hull window (the shared support-vertex cache), the run with --frames first differed
// at t = 1.38 s
constexpr const char* kScene = "scenes/tbar.yaml";
constexpr double kDuration = 1.45;  // s

// the lines of a text file
std::vector<std::string> Lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class OutputIndependenceTest : public testing::CliTest {
 protected:
  // the trajectory.csv lines of `ecpsim run kScene` with `options`, in a folder of its own
  std::vector<std::string> Trajectory(const std::string& options) {
    const fs::path out = dir_ / fmt::format("run{}", runs_++);
    const testing::CliResult result = Run(
        fmt::format("run {} -o '{}' --duration {} {}", kScene, out.string(), kDuration, options));
    EXPECT_EQ(result.exit_code, 0) << options << ":\n" << result.output;
    return Lines(out / "trajectory.csv");
  }

  int runs_ = 0;
};

TEST_F(OutputIndependenceTest, FramesVideoRateAndSizeLeaveTheTrajectoryByteIdentical) {
  const std::vector<std::string> plain = Trajectory("");
  // a header, the initial state and one row per step of h = 0.01 s
  ASSERT_EQ(plain.size(), 2u + 145u);
  std::vector<std::string> options = {
      "--frames --width 64 --height 48",            // the default 30 frames/s
      "--frames --fps 100 --width 64 --height 48",  // a frame after every step
      "--frames --fps 7 --width 96 --height 64",
  };
  if (std::system("command -v ffmpeg > /dev/null 2>&1") == 0) {
    options.push_back("--video --fps 24 --width 64 --height 48");
  }
  for (const std::string& option : options) {
    const std::vector<std::string> framed = Trajectory(option);
    ASSERT_EQ(framed.size(), plain.size()) << option;
    for (size_t row = 0; row < plain.size(); ++row) {
      ASSERT_EQ(framed[row], plain[row]) << option << ": row " << row;
    }
  }
}

TEST_F(OutputIndependenceTest, RowIntervalWritesTheSameRows) {
  const std::vector<std::string> plain = Trajectory("");
  std::map<std::string, std::string> by_time;  // row by its t column
  for (const std::string& row : plain) by_time[row.substr(0, row.find(','))] = row;
  const std::vector<std::string> sparse =
      Trajectory("--set output.every=5 --frames --fps 100 --width 64 --height 48");
  // the header, t = 0 and every fifth of the 145 steps (the last among them)
  ASSERT_EQ(sparse.size(), 2u + 29u);
  for (const std::string& row : sparse) {
    const auto match = by_time.find(row.substr(0, row.find(',')));
    ASSERT_NE(match, by_time.end()) << row;
    EXPECT_EQ(row, match->second);
  }
}

}  // namespace
}  // namespace ecpsim::app
