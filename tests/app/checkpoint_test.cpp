// `ecpsim run --resume DIR` (app/checkpoint.cpp, app/run_origin.cpp): a run interrupted half-way
// and resumed gives the same files as one that never stopped, bit for bit; a resume with other
// inputs or arguments is refused.

#include <signal.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "render/image_compare.h"
#include "render/png_writer.h"
#include "tests/app/run_fixture.h"
#include "tests/render/decode_video.h"

namespace ecpsim {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// the T-bar's first second at h = 1e-5 s: 10^5 steps (about a second of CPU), sliding and turning
// on changing contact modes, with warm starts and hull windows to carry over; a row every 7 steps,
// so the interrupt's own row (off that cadence) must be dropped on resume; 21 small frames as PNGs
// and a video
const std::vector<std::string> kTbarRun = {"run",        "scenes/tbar.yaml",
                                           "--dt",       "1e-5",
                                           "--duration", "1",
                                           "--set",      "output.every=7",
                                           "--frames",   "--video",
                                           "--fps",      "20",
                                           "--width",    "64",
                                           "--height",   "48"};
constexpr int kTbarFrames = 21;                     // t = 0, 0.05, …, 1 s
constexpr size_t kTbarRows = 1 + (100000 + 6) / 7;  // t = 0, every 7th step and the last one

// frames of the same state drawn by a renderer with another history (a fresh one after the
// resume) differ by at most 1 level in a few pixels (reported: the renderer's caches); a frame of
// another time differs in hundreds of pixels by far more
const render::CompareTolerance kSameFrame = {1, 0.002};

// how much further from the rendered frames (mean levels) the decoded frames of a video continued
// in segments may be than the worst frame of the video encoded in one go: each segment starts on
// a key frame and x264's constant-quality rate control (crf 18) holds every frame near one
// quality wherever it falls in a group of pictures (on the T-bar's frames both stay within 3 to 5
// levels); twice that catches a segment encoded otherwise or damaged by the join, while a frame
// of the wrong time is the nearest-frame check's to catch (neighbours differ by only 4 to 13)
constexpr double kSegmentedCodecSlack = 2.0;

class CheckpointTest : public testing::RunFixture {
 protected:
  std::vector<std::string> With(std::vector<std::string> arguments, const fs::path& out) {
    arguments.insert(arguments.end(), {"-o", out.string()});
    return arguments;
  }

  static std::string Read(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  // a copy of slide.yaml in the test folder, run for 10^4 s and stopped after 20 rows: a folder
  // with a checkpoint to resume
  fs::path InterruptedSlide() {
    fs::copy_file(fs::path(ECPSIM_SOURCE_DIR) / "scenes" / "slide.yaml", dir_ / "slide.yaml");
    const fs::path out = dir_ / "slide_out";
    const testing::ChildExit exit = InterruptAfterRows(
        {"run", (dir_ / "slide.yaml").string(), "-o", out.string(), "--duration", "1e4"}, out, 20,
        {SIGINT});
    EXPECT_EQ(exit.exit_code, 130) << log_;
    EXPECT_TRUE(fs::exists(out / "checkpoint.json"));
    return out;
  }
};

TEST_F(CheckpointTest, AResumedRunIsBitIdenticalToOneThatNeverStopped) {
  const fs::path whole = dir_ / "whole", parts = dir_ / "parts";
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", fmt::join(kTbarRun, " "), whole.string())).exit_code, 0);
  ASSERT_EQ(ReadLines(whole / "trajectory.csv").size(), 1 + kTbarRows);

  // stopped about half-way, then resumed from its checkpoint alone
  const testing::ChildExit exit =
      InterruptAfterRows(With(kTbarRun, parts), parts, kTbarRows / 2, {SIGINT});
  ASSERT_EQ(exit.exit_code, 130) << log_;
  const nlohmann::json stopped = ReadJson(parts / "summary.json");
  EXPECT_EQ(stopped["interrupted"], true);
  // rows 0, 7, 14, …: the (kTbarRows / 2)-th row is step 7 (kTbarRows / 2 − 1)
  EXPECT_GE(stopped["steps"].get<long>(), 7 * static_cast<long>(kTbarRows / 2 - 1));
  EXPECT_LT(stopped["steps"].get<long>(), 100000);
  const testing::CliResult resumed = Run(fmt::format("run --resume '{}'", parts.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;

  // the trajectory: the same bytes, hence the same doubles
  EXPECT_TRUE(Read(whole / "trajectory.csv") == Read(parts / "trajectory.csv"));
  // the summary: the same counts and extremes over the whole run
  const nlohmann::json a = ReadJson(whole / "summary.json"), b = ReadJson(parts / "summary.json");
  for (const char* key :
       {"steps", "rows", "t_end", "retries", "iterations_mean", "iterations_max", "residual_max",
        "substeps_max", "max_penetration", "converged", "interrupted"}) {
    EXPECT_EQ(a[key], b[key]) << key;
  }
  EXPECT_EQ(b["resumed_from_step"], stopped["steps"]);
  // the frames: all 21, each showing the same state; the video is encoded from all of them
  for (int k = 0; k < kTbarFrames; ++k) {
    const std::string name = fmt::format("frame_{:06d}.png", k);
    const render::ImageComparison comparison =
        render::CompareImages(render::ReadPng((whole / "frames" / name).string()),
                              render::ReadPng((parts / "frames" / name).string()), kSameFrame);
    EXPECT_TRUE(comparison.match) << name << ": " << comparison.Summary(kSameFrame);
  }
  EXPECT_FALSE(fs::exists(parts / "frames" / "frame_000021.png"));
  EXPECT_GT(fs::file_size(parts / "video.mp4"), fs::file_size(whole / "video.mp4") / 2);
  // a complete run leaves nothing to resume, and nothing temporary
  EXPECT_FALSE(fs::exists(parts / "checkpoint.json"));
  EXPECT_THAT(Leftovers(parts), ::testing::IsEmpty());
}

// the video of a resumed run is joined after its last step; a run whose join fails (here an
// ffmpeg that refuses the concat demuxer) — or that is killed during it — keeps the checkpoint
// and the earlier video, so the next resume still makes the whole video
TEST_F(CheckpointTest, AResumeWhoseVideoCannotBeJoinedStaysResumable) {
  const fs::path parts = dir_ / "parts", fake = dir_ / "fake_bin";
  std::vector<std::string> alone = kTbarRun;
  alone.erase(std::find(alone.begin(), alone.end(), "--frames"));
  ASSERT_EQ(InterruptAfterRows(With(alone, parts), parts, kTbarRows / 2, {SIGINT}).exit_code, 130)
      << log_;
  const size_t earlier = testing::DecodeVideo((parts / "video.mp4").string(), 64, 48).size();
  fs::create_directories(fake);
  std::ofstream(fake / "ffmpeg") << "#!/bin/sh\n"
                                    "for a in \"$@\"; do [ \"$a\" = concat ] && exit 1; done\n"
                                    "exec /usr/bin/ffmpeg \"$@\"\n";
  fs::permissions(fake / "ffmpeg", fs::perms::owner_all);
  const testing::CliResult failed = Run(fmt::format("run --resume '{}'", parts.string()),
                                        fmt::format("PATH='{}':/usr/bin", fake.string()));
  EXPECT_NE(failed.exit_code, 0) << failed.output;
  EXPECT_TRUE(fs::exists(parts / "checkpoint.json"));
  EXPECT_EQ(testing::DecodeVideo((parts / "video.mp4").string(), 64, 48).size(), earlier);
  // the trajectory is complete; the resume redoes the second half and joins the video
  const testing::CliResult resumed = Run(fmt::format("run --resume '{}'", parts.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(testing::DecodeVideo((parts / "video.mp4").string(), 64, 48).size(),
            static_cast<size_t>(kTbarFrames));
  EXPECT_FALSE(fs::exists(parts / "checkpoint.json"));
  EXPECT_THAT(Leftovers(parts), ::testing::IsEmpty());
}

// a video alone has no PNG frames to encode again: each part of the run adds its frames as a
// segment of the video, and the resumed video holds every frame of the run once, in order
TEST_F(CheckpointTest, AVideoAloneStoppedTwiceHoldsEveryFrameOnceInOrder) {
  const fs::path whole = dir_ / "whole", parts = dir_ / "parts";
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", fmt::join(kTbarRun, " "), whole.string())).exit_code, 0);
  std::vector<std::string> alone = kTbarRun;
  alone.erase(std::find(alone.begin(), alone.end(), "--frames"));

  // stopped at a third: the video holds the frames rendered up to there
  ASSERT_EQ(InterruptAfterRows(With(alone, parts), parts, kTbarRows / 3, {SIGINT}).exit_code, 130)
      << log_;
  const double t_stop = ReadJson(parts / "summary.json")["t_end"].get<double>();
  EXPECT_EQ(testing::DecodeVideo((parts / "video.mp4").string(), 64, 48).size(),
            static_cast<size_t>(std::floor(t_stop * 20 + 1e-5 * 20 / 2)) + 1);
  // resumed and stopped again at two thirds (the video then joins its two segments), resumed to
  // the end with its own command line
  ASSERT_EQ(
      InterruptAfterRows({"run", "--resume", parts.string()}, parts, 2 * kTbarRows / 3, {SIGINT})
          .exit_code,
      130)
      << log_;
  const testing::CliResult resumed = Run(fmt::format(
      "{} -o '{}' --resume '{}'", fmt::join(alone, " "), parts.string(), parts.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Read(whole / "trajectory.csv") == Read(parts / "trajectory.csv"));
  EXPECT_FALSE(fs::exists(parts / "frames"));
  EXPECT_FALSE(fs::exists(parts / "checkpoint.json"));
  EXPECT_THAT(Leftovers(parts), ::testing::IsEmpty());

  // the frames: as many as the uninterrupted run's, each nearest to the PNG of its own time
  const std::vector<render::Image> reference =
      testing::DecodeVideo((whole / "video.mp4").string(), 64, 48);
  const std::vector<render::Image> segmented =
      testing::DecodeVideo((parts / "video.mp4").string(), 64, 48);
  ASSERT_EQ(reference.size(), static_cast<size_t>(kTbarFrames));
  ASSERT_EQ(segmented.size(), static_cast<size_t>(kTbarFrames));
  std::vector<render::Image> pngs;
  double reference_error = 0;  // levels: the one-go video's worst frame against its PNG
  for (int k = 0; k < kTbarFrames; ++k) {
    pngs.push_back(
        render::ReadPng((whole / "frames" / fmt::format("frame_{:06d}.png", k)).string()));
    reference_error =
        std::max(reference_error, testing::MeanLevelDifference(reference[k], pngs[k]));
  }
  for (int k = 0; k < kTbarFrames; ++k) {
    EXPECT_EQ(testing::NearestImage(segmented[k], pngs), k) << "frame " << k;
    EXPECT_LE(testing::MeanLevelDifference(segmented[k], pngs[k]),
              kSegmentedCodecSlack * reference_error)
        << "frame " << k;
  }
}

TEST_F(CheckpointTest, AVideoAloneWithoutItsEarlierFramesIsNotResumed) {
  // a video that lost frames (replaced by a shorter one) cannot be continued into the whole run's
  const fs::path out = dir_ / "out";
  const std::vector<std::string> run = {
      "run", "scenes/slide.yaml", "-o", out.string(), "--duration", "1e4", "--video", "--fps",
      "100", "--width",           "64", "--height",   "48"};
  ASSERT_EQ(InterruptAfterRows(run, out, 20, {SIGINT}).exit_code, 130) << log_;
  fs::remove(out / "video.mp4");
  const testing::CliResult missing = Run(fmt::format("run --resume '{}'", out.string()));
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("video.mp4: missing; the run to resume rendered"));
  EXPECT_THAT(missing.output, HasSubstr("so the video cannot be continued"));
  EXPECT_TRUE(fs::exists(out / "checkpoint.json"));
}

// bodies touching moving bodies: a contact's warm start carries G's multipliers by G's window,
// which the checkpoint must hold too. Without it the resumed warm start had l_G = 0 (residual ≈
// 1), another guess solved the step, and the pushed box's trajectory left the uninterrupted one
// in the first step after the resume (as did the gripper's and the dominoes')
TEST_F(CheckpointTest, AResumedPushIsBitIdenticalToOneThatNeverStopped) {
  // 10^4 steps (half a second of CPU) of the pusher carrying the box, a row every 10
  const std::vector<std::string> push = {
      "run", "scenes/push_box.yaml", "--dt", "1e-4", "--duration", "1", "--set", "output.every=10"};
  const fs::path whole = dir_ / "whole", parts = dir_ / "parts";
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", fmt::join(push, " "), whole.string())).exit_code, 0);
  const size_t rows = ReadLines(whole / "trajectory.csv").size() - 1;
  const testing::ChildExit exit = InterruptAfterRows(With(push, parts), parts, rows / 2, {SIGINT});
  ASSERT_EQ(exit.exit_code, 130) << log_;
  const testing::CliResult resumed = Run(fmt::format("run --resume '{}'", parts.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Read(whole / "trajectory.csv") == Read(parts / "trajectory.csv"));
}

// bodies made of parts: a contact per pair of parts, each with its warm start, between a mug of
// eight parts and a kinematic hook of two (engine/README.md, "Bodies made of convex parts")
TEST_F(CheckpointTest, AResumedHookLiftingAMugIsBitIdenticalToOneThatNeverStopped) {
  // 600 steps (2 s of CPU), a row each
  const std::vector<std::string> hook = {"run", "scenes/hook.yaml"};
  const fs::path whole = dir_ / "whole", parts = dir_ / "parts";
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", fmt::join(hook, " "), whole.string())).exit_code, 0);
  const size_t rows = ReadLines(whole / "trajectory.csv").size() - 1;
  const testing::ChildExit exit = InterruptAfterRows(With(hook, parts), parts, rows / 2, {SIGINT});
  ASSERT_EQ(exit.exit_code, 130) << log_;
  const testing::CliResult resumed = Run(fmt::format("run --resume '{}'", parts.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Read(whole / "trajectory.csv") == Read(parts / "trajectory.csv"));
}

// sleeping islands (engine/README.md, "Sleeping islands"): which steps of the stack replay and
// which are solved (every 32nd of its rest) follows the count of its steps at rest, which the
// checkpoint must hold; without it the resumed stack stays awake 10 steps, its residuals and
// sleeping_body_steps differ
TEST_F(CheckpointTest, AResumedSleepingStackIsBitIdenticalToOneThatNeverStopped) {
  // 10^5 steps, 97 % of them asleep (0.3 s of CPU), a row every 100
  const std::vector<std::string> stack = {"run",   "scenes/stack.yaml", "--duration",
                                          "1000",  "--set",             "solver.sleep=true",
                                          "--set", "output.every=100"};
  const fs::path whole = dir_ / "whole", parts = dir_ / "parts";
  ASSERT_EQ(Run(fmt::format("{} -o '{}'", fmt::join(stack, " "), whole.string())).exit_code, 0);
  const testing::ChildExit exit = InterruptAfterRows(With(stack, parts), parts, 300, {SIGINT});
  ASSERT_EQ(exit.exit_code, 130) << log_;
  const testing::CliResult resumed = Run(fmt::format("run --resume '{}'", parts.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Read(whole / "trajectory.csv") == Read(parts / "trajectory.csv"));
  const nlohmann::json a = ReadJson(whole / "summary.json"), b = ReadJson(parts / "summary.json");
  EXPECT_GT(a["sleeping_body_steps"].get<long>(), 0);
  EXPECT_EQ(a["sleeping_body_steps"], b["sleeping_body_steps"]);
  EXPECT_EQ(a["iterations_mean"], b["iterations_mean"]);
  EXPECT_EQ(a["residual_max"], b["residual_max"]);
}

TEST_F(CheckpointTest, AChangedSceneFileIsRefused) {
  const fs::path out = InterruptedSlide();
  const std::string trajectory = Read(out / "trajectory.csv");
  std::ofstream(dir_ / "slide.yaml", std::ios::app) << "# edited after the run began\n";
  const testing::CliResult result = Run(fmt::format("run --resume '{}'", out.string()));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("slide.yaml or a mesh it names has changed since the run "
                                       "began"));
  // nothing is touched: the run can still be resumed once the file is restored
  EXPECT_TRUE(fs::exists(out / "checkpoint.json"));
  EXPECT_TRUE(Read(out / "trajectory.csv") == trajectory);
}

TEST_F(CheckpointTest, OtherArgumentsOrAnotherFolderAreRefused) {
  const fs::path out = InterruptedSlide();
  const std::string slide = (dir_ / "slide.yaml").string();
  struct Case {
    std::string arguments, message;
  };
  const std::vector<Case> cases = {
      // another duration than the run's
      {fmt::format("run '{}' --duration 2 --resume '{}'", slide, out.string()),
       "give its command line exactly"},
      // an option without the scene
      {fmt::format("run --dt 0.001 --resume '{}'", out.string()), "give its command line exactly"},
      // another output folder
      {fmt::format("run --resume '{}' -o '{}'", out.string(), (dir_ / "other").string()),
       "a resumed run writes into its own folder"},
      // a folder without a checkpoint
      {fmt::format("run --resume '{}'", dir_.string()), "nothing to resume"},
      // a checkpoint that is not one
      {fmt::format("run --resume '{}'", (dir_ / "broken").string()), "not a checkpoint of ecpsim"},
  };
  fs::create_directories(dir_ / "broken");
  std::ofstream(dir_ / "broken" / "checkpoint.json") << R"({"format": 1, "origin": {}})";
  for (const Case& c : cases) {
    const testing::CliResult result = Run(c.arguments);
    EXPECT_EQ(result.exit_code, 1) << c.arguments << ": " << result.output;
    EXPECT_THAT(result.output, HasSubstr(c.message)) << c.arguments;
  }
  EXPECT_TRUE(fs::exists(out / "checkpoint.json"));

  // a checkpoint of another ecpsim build: its engine may step differently
  nlohmann::json checkpoint = ReadJson(out / "checkpoint.json");
  checkpoint["origin"]["ecpsim"] = "ecpsim 0.0.1 (git 000000000000)";
  std::ofstream(out / "checkpoint.json") << checkpoint.dump();
  const testing::CliResult result = Run(fmt::format("run --resume '{}'", out.string()));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("written by ecpsim 0.0.1 (git 000000000000), this is "
                                       "ecpsim "));
}

TEST_F(CheckpointTest, TheRunsOwnCommandLineIsAccepted) {
  // the same command line again, with --resume: it continues (and is stopped again at once)
  const fs::path out = InterruptedSlide();
  const long first_stop = ReadJson(out / "summary.json")["steps"].get<long>();
  const testing::ChildExit exit =
      InterruptAfterRows({"run", (dir_ / "slide.yaml").string(), "-o", out.string(), "--duration",
                          "1e4", "--resume", out.string()},
                         out, first_stop + 20, {SIGTERM});
  EXPECT_EQ(exit.exit_code, 143) << log_;
  const nlohmann::json summary = ReadJson(out / "summary.json");
  EXPECT_EQ(summary["resumed_from_step"].get<long>(), first_stop);
  EXPECT_GT(summary["steps"].get<long>(), first_stop);
  ExpectConsistentInterruptedRun(out, "SIGTERM");
}

TEST_F(CheckpointTest, AnInterruptedDropIsResumedToo) {
  // `ecpsim run --resume` rebuilds a drop's scene from its stored options
  const fs::path out = dir_ / "drop";
  const std::vector<std::string> drop = {
      "drop", "tests/fixtures/meshes/box.obj", "-o", out.string(), "--height", "0.05", "--duration",
      "1e4"};
  ASSERT_EQ(InterruptAfterRows(drop, out, 20, {SIGINT}).exit_code, 130) << log_;
  const long first_stop = ReadJson(out / "summary.json")["steps"].get<long>();
  const testing::ChildExit exit =
      InterruptAfterRows({"run", "--resume", out.string()}, out, first_stop + 20, {SIGINT});
  EXPECT_EQ(exit.exit_code, 130) << log_;
  EXPECT_EQ(ReadJson(out / "summary.json")["resumed_from_step"].get<long>(), first_stop);
  ExpectConsistentInterruptedRun(out, "SIGINT");
}

TEST_F(CheckpointTest, ResumingAFailedRunReproducesTheFailureAtOnce) {
  // one Newton iteration cannot solve the tilted box's first contact step: the run stops on a
  // solver failure with a checkpoint just before the failing step
  const fs::path out = dir_ / "fail";
  const std::string arguments =
      fmt::format("run scenes/tilted_box.yaml -o '{}' --set solver.max_iterations=1", out.string());
  const testing::CliResult first = Run(arguments);
  ASSERT_EQ(first.exit_code, 3) << first.output;
  const nlohmann::json failed = ReadJson(out / "summary.json");
  ASSERT_TRUE(fs::exists(out / "checkpoint.json"));

  const testing::CliResult again = Run(fmt::format("run --resume '{}'", out.string()));
  EXPECT_EQ(again.exit_code, 3) << again.output;
  const nlohmann::json resumed = ReadJson(out / "summary.json");
  EXPECT_EQ(resumed["resumed_from_step"], failed["steps"]);
  EXPECT_EQ(resumed["steps"], failed["steps"]);
  EXPECT_EQ(resumed["error"], failed["error"]);
  EXPECT_EQ(ReadLines(out / "trajectory.csv").size(), 1 + failed["rows"].get<size_t>());
}

TEST_F(CheckpointTest, ANewRunIntoTheFolderRemovesTheCheckpoint) {
  const fs::path out = InterruptedSlide();
  const testing::CliResult result = Run(fmt::format("run scenes/slide.yaml -o '{}'", out.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_FALSE(fs::exists(out / "checkpoint.json"));
}

TEST_F(CheckpointTest, SceneOrResumeIsRequired) {
  const testing::CliResult result = Run(fmt::format("run -o '{}'", (dir_ / "o").string()));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("scene is required"));
}

}  // namespace
}  // namespace ecpsim
