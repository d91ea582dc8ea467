// Runs the built `ecpsim` binary with --frames/--video and `ecpsim render`, and checks the images
// and videos.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "render/png_writer.h"
#include "tests/cli_test.h"
#include "tests/render/decode_video.h"

namespace ecpsim::render {
namespace {

namespace fs = std::filesystem;

class FramesCommandTest : public testing::CliTest {
 protected:
  // exit code of `ecpsim ARGUMENTS`; its output in log_
  int Run(const std::string& arguments, const std::string& environment = "") {
    const testing::CliResult result = CliTest::Run(arguments, environment);
    log_ = result.output;
    return result.exit_code;
  }

  std::string log_;
};

TEST_F(FramesCommandTest, FramesFollowTheFrameRateNotTheStep) {
  // slide.yaml: 0.5 s at h = 0.01; at 10 frames/s the frames are t = 0, 0.1, ..., 0.5
  const fs::path out = dir_ / "out";
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --fps 10 --width 64 "
                            "--height 48",
                            out.string())),
            0)
      << log_;
  int count = 0;
  for (const auto& entry : fs::directory_iterator(out / "frames")) {
    const Image image = ReadPng(entry.path().string());
    EXPECT_EQ(image.width, 64);
    EXPECT_EQ(image.height, 48);
    ++count;
  }
  EXPECT_EQ(count, 6);
  EXPECT_TRUE(fs::exists(out / "frames" / "frame_000005.png"));
  EXPECT_FALSE(fs::exists(out / "video.mp4"));
}

TEST_F(FramesCommandTest, VideoIsWrittenNextToTheFrames) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --video --fps 20 --width 64 "
                            "--height 48",
                            out.string())),
            0)
      << log_;
  ASSERT_TRUE(fs::exists(out / "video.mp4"));
  // an MP4 starts with an ftyp box; 11 frames of H.264 are more than a header
  std::ifstream video(out / "video.mp4", std::ios::binary);
  char head[8] = {};
  video.read(head, 8);
  EXPECT_EQ(std::string(head + 4, 4), "ftyp");
  EXPECT_GT(fs::file_size(out / "video.mp4"), 1000u);
  EXPECT_TRUE(fs::exists(out / "frames" / "frame_000010.png"));
}

// how much further from the rendered frames (mean levels) a video alone's decoded frames may be
// than those of the video made with PNG frames: a video alone hands ffmpeg B, G, R bytes, whose
// conversion to yuv420p is swscale's unscaled one (coarser chroma: on the desk 39.3 against 40.1
// dB PSNR, docs/rendering.md); on the slide's 64×48 frames the video alone is 3.4 to 3.8
// levels off, 1.13× the other's 3.0 to 3.4; 1.5 leaves room for the chroma, while a frame of
// another time is the nearest-frame check's to catch
constexpr double kBgrConversionSlack = 1.5;

TEST_F(FramesCommandTest, AVideoAloneShowsTheFramesOfTheVideoWithPngFrames) {
  // slide.yaml: 0.5 s at 20 frames/s = 11 frames, t = 0 to 0.5
  const fs::path both = dir_ / "both", alone = dir_ / "alone";
  const std::string options = "--fps 20 --width 64 --height 48";
  ASSERT_EQ(
      Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --video {}", both.string(), options)),
      0)
      << log_;
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --video {}", alone.string(), options)),
            0)
      << log_;
  EXPECT_THAT(log_, ::testing::HasSubstr(fmt::format("11 frames in {}/video.mp4", alone.string())));
  EXPECT_FALSE(fs::exists(alone / "frames"));
  const std::vector<Image> with_pngs = testing::DecodeVideo((both / "video.mp4").string(), 64, 48);
  const std::vector<Image> without = testing::DecodeVideo((alone / "video.mp4").string(), 64, 48);
  ASSERT_EQ(with_pngs.size(), 11u);
  ASSERT_EQ(without.size(), 11u);
  // each frame shows its own PNG's time, in order (H.264 is lossy: nearest, not equal), about as
  // closely as the video made with the PNGs
  std::vector<Image> pngs;
  for (int k = 0; k < 11; ++k) {
    pngs.push_back(ReadPng((both / "frames" / fmt::format("frame_{:06d}.png", k)).string()));
  }
  for (int k = 0; k < 11; ++k) {
    EXPECT_EQ(testing::NearestImage(without[k], pngs), k);
    EXPECT_LE(testing::MeanLevelDifference(without[k], pngs[k]),
              kBgrConversionSlack * testing::MeanLevelDifference(with_pngs[k], pngs[k]))
        << "frame " << k;
  }
}

TEST_F(FramesCommandTest, AVideoAloneAlsoWorksForDrop) {
  const fs::path out = dir_ / "drop";
  ASSERT_EQ(Run(fmt::format("drop tests/fixtures/meshes/box.obj -o '{}' --height 0.05 "
                            "--duration 0.1 --video",
                            out.string())),
            0)
      << log_;
  EXPECT_FALSE(fs::exists(out / "frames"));
  // 30 frames/s (the default) over 0.1 s: t = 0, 1/30, 2/30, 3/30; 1280×720 (the default size)
  EXPECT_EQ(testing::DecodeVideo((out / "video.mp4").string(), 1280, 720).size(), 4u);
}

TEST_F(FramesCommandTest, AVideoAloneWithoutFfmpegStopsBeforeTouchingTheFolder) {
  // an earlier run's frames, trajectory and summary in the folder
  const fs::path out = dir_ / "out";
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --fps 10 --width 64 "
                            "--height 48 --duration 0.2",
                            out.string())),
            0)
      << log_;
  const auto trajectory_time = fs::last_write_time(out / "trajectory.csv");
  EXPECT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --video --fps 10 --width 64 "
                            "--height 48",
                            out.string()),
                "PATH=/nonexistent"),
            1)
      << log_;
  EXPECT_THAT(log_, ::testing::HasSubstr("the program 'ffmpeg' is not on PATH; install the "
                                         "Debian package ffmpeg"));
  EXPECT_TRUE(fs::exists(out / "frames" / "frame_000002.png"));
  EXPECT_EQ(fs::last_write_time(out / "trajectory.csv"), trajectory_time);
  EXPECT_FALSE(fs::exists(out / "video.mp4"));
}

TEST_F(FramesCommandTest, AVideoAloneRemovesTheEarlierRunsFramesAndTheirFolder) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --fps 10 --width 64 "
                            "--height 48",
                            out.string())),
            0)
      << log_;
  ASSERT_TRUE(fs::exists(out / "frames" / "frame_000005.png"));
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --video --fps 10 --width 64 "
                            "--height 48",
                            out.string())),
            0)
      << log_;
  // frames of another run would pass for this one's: they go, and the folder they leave empty
  EXPECT_FALSE(fs::exists(out / "frames"));
  EXPECT_EQ(testing::DecodeVideo((out / "video.mp4").string(), 64, 48).size(), 6u);
}

TEST_F(FramesCommandTest, MissingFfmpegIsAClearErrorAndTheFramesStay) {
  const fs::path out = dir_ / "out";
  // PATH without ffmpeg (the binary itself is started by its full path)
  EXPECT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --video --fps 10 --width 64 "
                            "--height 48",
                            out.string()),
                "PATH=/nonexistent"),
            1)
      << log_;
  EXPECT_NE(log_.find("ffmpeg"), std::string::npos) << log_;
  EXPECT_TRUE(fs::exists(out / "frames" / "frame_000005.png"));
  EXPECT_TRUE(fs::exists(out / "trajectory.csv"));
  EXPECT_FALSE(fs::exists(out / "video.mp4"));
}

TEST_F(FramesCommandTest, ARerunRemovesTheEarlierRunsFramesAndVideoOnly) {
  // a run at 20 frames/s with video, then one at 10 frames/s without, into the same folder
  const fs::path out = dir_ / "out";
  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --video --fps 20 --width 64 "
                            "--height 48",
                            out.string())),
            0)
      << log_;
  ASSERT_TRUE(fs::exists(out / "frames" / "frame_000010.png"));
  // what is not a frame of ours stays: the user's notes, a link named like a frame, and a
  // temporary file of a process that is still running (this test)
  std::ofstream(out / "frames" / "notes.txt") << "keep";
  std::ofstream(dir_ / "elsewhere.png") << "keep";
  fs::create_symlink(dir_ / "elsewhere.png", out / "frames" / "frame_000020.png");
  const std::string running = fmt::format("frame_000021.png.tmp-{}-0", getpid());
  std::ofstream(out / "frames" / running) << "keep";
  // a temporary file of a process that has ended goes (a PID above pid_max, which is 2^22)
  std::ofstream(out / "frames" / "frame_000022.png.tmp-999999999-0") << "stale";

  ASSERT_EQ(Run(fmt::format("run scenes/slide.yaml -o '{}' --frames --fps 10 --width 64 "
                            "--height 48",
                            out.string())),
            0)
      << log_;
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(out / "frames")) {
    names.insert(entry.path().filename().string());
  }
  const std::set<std::string> expected = {
      "frame_000000.png", "frame_000001.png", "frame_000002.png",
      "frame_000003.png", "frame_000004.png", "frame_000005.png",
      "frame_000020.png", "notes.txt",        running};
  EXPECT_EQ(names, expected);
  EXPECT_TRUE(fs::is_symlink(out / "frames" / "frame_000020.png"));
  EXPECT_FALSE(fs::exists(out / "video.mp4"));  // the earlier run's video is not this run's
}

TEST_F(FramesCommandTest, RenderIsDeterministic) {
  const fs::path a = dir_ / "a.png", b = dir_ / "b.png";
  const std::string args = "render scenes/tilted_box.yaml --time 0.3 --width 160 --height 120";
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", args, a.string())), 0) << log_;
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", args, b.string())), 0) << log_;
  const Image first = ReadPng(a.string()), second = ReadPng(b.string());
  ASSERT_EQ(first.pixels.size(), second.pixels.size());
  EXPECT_TRUE(first.pixels == second.pixels);
  EXPECT_EQ(Run(fmt::format("compare '{}' '{}'", a.string(), b.string())), 0) << log_;
}

TEST_F(FramesCommandTest, RenderRejectsATimeOutsideTheScene) {
  // negative, beyond the scene's 0.5 s (it would step past its duration, forever for 1e300)
  for (const char* time : {"-1", "0.6", "1e300", "nan"}) {
    EXPECT_EQ(Run(fmt::format("render scenes/slide.yaml --time {} -o '{}'", time,
                              (dir_ / "x.png").string())),
              1)
        << time;
    EXPECT_THAT(log_, ::testing::HasSubstr(fmt::format("--time = {}: expected", time)));
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

}  // namespace
}  // namespace ecpsim::render
