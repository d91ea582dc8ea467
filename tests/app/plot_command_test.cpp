// Runs the built `ecpsim plot` on short runs of the paper's scenes and checks the PNG files it
// writes (gnuplot must be installed: scripts/setup.sh installs gnuplot-nox).

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "render/png_writer.h"
#include "tests/cli_test.h"

namespace ecpsim {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// a PNG starts with these 8 bytes (PNG specification, section 5.2)
constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
// the smallest of our plots (one curve, axes, labels, 1000 × 340 pixels) compresses to well over
// 10 kB; a blank or truncated image is far smaller
constexpr std::uintmax_t kMinPlotBytes = 10000;

class PlotCommandTest : public testing::CliTest {
 protected:
  // a short run of scenes/NAME.yaml into dir_/NAME (the scene path absolute, as summary.json
  // then names it, so that `ecpsim plot` finds it from any folder)
  fs::path RunScene(const std::string& name, double duration) {
    const fs::path out = dir_ / name;
    const std::string scene = std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + name + ".yaml";
    const testing::CliResult run =
        Run(fmt::format("run '{}' -o '{}' --duration {}", scene, out.string(), duration));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return out;
  }

  static void ExpectValidPng(const fs::path& path) {
    ASSERT_TRUE(fs::exists(path)) << path;
    EXPECT_GE(fs::file_size(path), kMinPlotBytes) << path;
    std::ifstream in(path, std::ios::binary);
    unsigned char head[8] = {};
    in.read(reinterpret_cast<char*>(head), 8);
    ASSERT_EQ(in.gcount(), 8) << path;
    for (int i = 0; i < 8; ++i) EXPECT_EQ(head[i], kPngSignature[i]) << path << " byte " << i;
  }

  // nothing but the run's files and the PNGs: no .partial, no gnuplot input left behind
  static void ExpectNoLeftovers(const fs::path& dir) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "trajectory.csv" || name == "summary.json" ||
                  entry.path().extension() == ".png")
          << "left behind: " << entry.path();
    }
  }
};

TEST_F(PlotCommandTest, DumbbellRunGivesCmPlotAndPatchSnapshots) {
  const fs::path out = RunScene("dumbbell", 0.6);
  const testing::CliResult plot = Run(fmt::format("plot '{}'", out.string()));
  ASSERT_EQ(plot.exit_code, 0) << plot.output;
  EXPECT_THAT(plot.output, HasSubstr("dumbbell_cm.png"));
  ExpectValidPng(out / "dumbbell_cm.png");
  ExpectValidPng(out / "dumbbell_patches.png");
  ExpectNoLeftovers(out);
}

TEST_F(PlotCommandTest, TBarRunGivesEcpHeightModeAndSnapshotPlots) {
  const fs::path out = RunScene("tbar", 0.5);
  const testing::CliResult plot = Run(fmt::format("plot '{}' --scene tbar", out.string()));
  ASSERT_EQ(plot.exit_code, 0) << plot.output;
  for (const char* png : {"tbar_ecp.png", "tbar_qz.png", "tbar_vz_ax.png", "tbar_patches.png"}) {
    ExpectValidPng(out / png);
  }
  ExpectNoLeftovers(out);
}

// pixels of exactly the colour (r, g, b) in the PNG at `path`: a curve's colour, anti-aliased
// at its edges only
long PixelsOfColour(const fs::path& path, int r, int g, int b) {
  const render::Image image = render::ReadPng(path.string());
  long count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.Pixel(x, y);
      count += p[0] == r && p[1] == g && p[2] == b;
    }
  return count;
}

TEST_F(PlotCommandTest, SeveralBodiesAreCurvesOfTheirOwnWithALegend) {
  const fs::path out = RunScene("gripper", 0.3);
  const testing::CliResult plot = Run(fmt::format("plot '{}'", out.string()));
  ASSERT_EQ(plot.exit_code, 0) << plot.output;
  ExpectValidPng(out / "position.png");
  ExpectValidPng(out / "velocity.png");
  // the box, left_jaw and right_jaw in the first three colours (#1f5fbf, #d62728, #2ca02c):
  // each one's curves and legend sample; 200 pixels is a short line segment
  constexpr long kCurvePixels = 200;
  for (const char* png : {"position.png", "velocity.png"}) {
    EXPECT_GT(PixelsOfColour(out / png, 0x1f, 0x5f, 0xbf), kCurvePixels) << png;
    EXPECT_GT(PixelsOfColour(out / png, 0xd6, 0x27, 0x28), kCurvePixels) << png;
    EXPECT_GT(PixelsOfColour(out / png, 0x2c, 0xa0, 0x2c), kCurvePixels) << png;
  }
  ExpectNoLeftovers(out);
}

TEST_F(PlotCommandTest, DeskPlotsTheOtherModelsWhenTheirTrajectoriesAreThere) {
  const fs::path out = RunScene("desk", 0.2);
  // a stand-in for another model's run of the same scene: the same trajectory
  fs::copy_file(out / "trajectory.csv", out / "trajectory_planar.csv");
  const testing::CliResult plot = Run(fmt::format("plot '{}'", out.string()));
  ASSERT_EQ(plot.exit_code, 0) << plot.output;
  ExpectValidPng(out / "desk_velocity.png");
  ExpectValidPng(out / "desk_patches.png");
}

TEST_F(PlotCommandTest, SiblingTrajectoryWithOtherTimesIsRejected) {
  const fs::path out = RunScene("desk", 0.2);
  std::ofstream(out / "trajectory_multipatch.csv") << "t,vx,wz\n0,0,0\n";
  const testing::CliResult plot = Run(fmt::format("plot '{}' --scene desk", out.string()));
  EXPECT_EQ(plot.exit_code, 1);
  EXPECT_THAT(plot.output, HasSubstr("trajectory_multipatch.csv: 1 rows"));
}

TEST_F(PlotCommandTest, MissingTrajectoryIsAOneLineError) {
  const testing::CliResult plot = Run(fmt::format("plot '{}'", (dir_ / "nothing").string()));
  EXPECT_EQ(plot.exit_code, 1);
  EXPECT_THAT(plot.output, HasSubstr("trajectory.csv: cannot read it"));
}

TEST_F(PlotCommandTest, BadCsvFieldIsNamed) {
  fs::create_directories(dir_ / "bad");
  std::ofstream(dir_ / "bad" / "trajectory.csv") << "t,px\n0,0\n0.01,nan\n";
  const testing::CliResult plot =
      Run(fmt::format("plot '{}' --scene generic", (dir_ / "bad").string()));
  EXPECT_EQ(plot.exit_code, 1);
  EXPECT_THAT(plot.output, HasSubstr("trajectory.csv:3: px = \"nan\": expected a finite number"));
}

TEST_F(PlotCommandTest, MissingGnuplotIsAClearError) {
  const fs::path out = RunScene("dumbbell", 0.05);
  const testing::CliResult plot = Run(fmt::format("plot '{}'", out.string()), "PATH=/nonexistent");
  EXPECT_EQ(plot.exit_code, 1);
  EXPECT_THAT(plot.output, HasSubstr("gnuplot: not found on PATH"));
  EXPECT_FALSE(fs::exists(out / "dumbbell_cm.png"));
}

TEST_F(PlotCommandTest, UnknownSceneKindIsRejected) {
  const testing::CliResult plot = Run(fmt::format("plot '{}' --scene chair", dir_.string()));
  EXPECT_EQ(plot.exit_code, 1);
  EXPECT_THAT(plot.output, HasSubstr("--scene = chair: expected desk, tbar, dumbbell"));
}

}  // namespace
}  // namespace ecpsim
