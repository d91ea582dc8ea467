// `ecpsim run SCENE -o DIR` and `ecpsim drop MESH -o DIR`: simulate and write the trajectory;
// `ecpsim run --resume DIR` continues a run that stopped early.

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/checkpoint.h"
#include "app/commands.h"
#include "app/frame_recorder.h"
#include "app/interrupt.h"
#include "app/option_checks.h"
#include "app/output_folder.h"
#include "app/run_origin.h"
#include "app/simulation_run.h"
#include "common/errors.h"
#include "engine/scene_io/drop_scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "render/ffmpeg_pipe.h"

namespace ecpsim::app {
namespace {

void PrintResult(const RunSummary& summary, const std::string& out_dir) {
  std::printf(
      "%ld steps, %.2f Newton iterations per step (max %d), %ld retries, max "
      "penetration %.3g m, median step %.1f us; wrote %s/trajectory.csv and "
      "%s/summary.json\n",
      summary.steps, summary.iterations_mean, summary.iterations_max, summary.retries,
      summary.max_penetration, summary.median_step_us, out_dir.c_str(), out_dir.c_str());
}

// threads beyond the cores of any machine it runs on are a typing error
constexpr int kMaxThreads = 1024;

// every core the machine has: islands solve side by side (1 where it does not say)
int DefaultThreads() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

struct RunOptions {
  std::string scene;
  std::string out_dir;
  std::optional<double> h;
  std::optional<double> duration;
  std::vector<std::string> overrides;
  std::string model;
  bool frames = false;
  bool video = false;
  std::optional<double> fps;
  std::optional<int> width, height;
  std::string resume;  // --resume DIR
  // --threads: the result is the same for any number, so it is not one of the run's arguments
  int threads = DefaultThreads();
};

// the scene overrides that `ecpsim run`'s options stand for, in a fixed order
std::vector<std::string> Overrides(const RunOptions& options) {
  std::vector<std::string> overrides = options.overrides;
  if (!options.model.empty()) overrides.push_back("model=" + options.model);
  if (options.fps) overrides.push_back(fmt::format("output.fps={}", *options.fps));
  if (options.width) overrides.push_back(fmt::format("output.width={}", *options.width));
  if (options.height) overrides.push_back(fmt::format("output.height={}", *options.height));
  if (options.h) overrides.push_back(fmt::format("h={}", *options.h));
  if (options.duration) overrides.push_back(fmt::format("duration={}", *options.duration));
  return overrides;
}

// what a run's arguments (RunArguments, DropArguments) ask to record
FrameOutputs FrameOutputsOf(const nlohmann::json& arguments) {
  return {arguments.at("frames").get<bool>(), arguments.at("video").get<bool>()};
}

// where the frames went, for the run's closing line
std::string FramePlaces(FrameOutputs outputs, const std::string& out_dir) {
  if (!outputs.video) return out_dir + "/frames";
  if (!outputs.frames) return out_dir + "/video.mp4";
  return fmt::format("{}/frames and {}/video.mp4", out_dir, out_dir);
}

// runs the scene, recording frames when its origin asks for them; frames and video are finished
// also when the run stops on a failure, so what was rendered stays valid
RunSummary RunWithFrames(const engine::LoadedScene& loaded, const std::string& out_dir,
                         RunSetup setup) {
  const FrameOutputs outputs = FrameOutputsOf(setup.origin.at("arguments"));
  setup.progress = isatty(fileno(stderr)) == 1;
  if (!outputs.frames && !outputs.video) return RunSimulation(loaded, out_dir, setup);
  FrameRecorder recorder(loaded, out_dir, outputs, setup.resume ? &setup.resume->state : nullptr);
  // a resumed run's checkpoint stays until the frames and the video are finished
  setup.keep_checkpoint = true;
  setup.observer = [&](const engine::State& state, const engine::StepReport& report) {
    recorder.Observe(state, report);
  };
  RunSummary summary;
  try {
    summary = RunSimulation(loaded, out_dir, setup);
  } catch (...) {
    try {
      recorder.Finish();
    } catch (const std::exception&) {
      // the run's own error is the one to report
    }
    throw;
  }
  recorder.Finish();
  if (summary.interrupt_signal == 0) RemoveCheckpoint(out_dir);
  std::printf("%d frames in %s\n", recorder.frames(), FramePlaces(outputs, out_dir).c_str());
  return summary;
}

// runs the scene described by `arguments` (RunArguments, DropArguments) with SIGINT and SIGTERM
// caught and prints the result; an interrupted run throws Interrupted once its outputs are
// complete (main() exits 130 or 143). `resume`: the checkpoint to continue from, its origin
// already checked.
void RunAndReport(const engine::LoadedScene& loaded, const std::string& out_dir,
                  const nlohmann::json& arguments, int threads,
                  const Checkpoint* resume = nullptr) {
  RunSetup setup;
  setup.threads = threads;
  setup.origin = RunOrigin(arguments, loaded.scene);
  setup.resume = resume;
  // a video alone needs ffmpeg: without it the run would make nothing that was asked for, so it
  // stops before the folder is touched (with PNG frames, the frames are made and the run says so)
  const FrameOutputs outputs = FrameOutputsOf(arguments);
  if (outputs.video && !outputs.frames) {
    render::RequireVideoProgram((std::filesystem::path(out_dir) / "video.mp4").string());
  }
  PrepareOutputFolder(out_dir, resume != nullptr);
  const InterruptGuard guard;
  const RunSummary summary = RunWithFrames(loaded, out_dir, setup);
  PrintResult(summary, out_dir);
  if (summary.interrupt_signal != 0) {
    throw Interrupted(summary.interrupt_signal,
                      fmt::format("interrupted by {} at t = {} s after {} of {} steps; the outputs "
                                  "in {} are complete up to there; continue with: ecpsim run "
                                  "--resume {}",
                                  SignalName(summary.interrupt_signal), summary.t_end,
                                  summary.steps, summary.planned_steps, out_dir, out_dir));
  }
}

// `ecpsim run --resume DIR [the run's own SCENE and options]`: continues the run in DIR from its
// checkpoint, with the scene and settings it began with
void Resume(const RunOptions& given) {
  const std::string dir = given.resume;
  const std::string path = (std::filesystem::path(dir) / "checkpoint.json").string();
  const Checkpoint checkpoint = ReadCheckpoint(path);
  const nlohmann::json& arguments = checkpoint.origin.at("arguments");
  std::error_code error;
  if (!given.out_dir.empty() && !std::filesystem::equivalent(given.out_dir, dir, error)) {
    throw InputError(
        fmt::format("--resume {} -o {}: a resumed run writes into its own folder; "
                    "leave out -o or give the same folder",
                    dir, given.out_dir));
  }
  // a command line given with --resume must be the run's own
  const bool more_given = !Overrides(given).empty() || given.frames || given.video;
  if (!given.scene.empty() || more_given) {
    if (given.scene.empty() ||
        RunArguments(given.scene, Overrides(given), given.frames, given.video) != arguments) {
      throw InputError(
          fmt::format("--resume {}: the run there is `{} -o {}`; give its command "
                      "line exactly, or nothing but --resume DIR",
                      dir, CommandLine(arguments), dir));
    }
  }
  const engine::LoadedScene loaded = SceneOf(arguments);
  RequireSameOrigin(checkpoint.origin, RunOrigin(arguments, loaded.scene), path);
  CheckFitsScene(checkpoint, loaded.scene, path);
  RunAndReport(loaded, dir, arguments, given.threads, &checkpoint);
}

}  // namespace

void PrintWarnings(const engine::LoadedScene& loaded) {
  for (const std::string& warning : loaded.warnings) {
    std::fprintf(stderr, "ecpsim: warning: %s\n", warning.c_str());
  }
}

void AddRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = app.add_subcommand(
      "run",
      "Simulate a YAML scene (docs/scene_format.md); writes DIR/trajectory.csv and "
      "DIR/summary.json");
  run->add_option("scene", options->scene, "scene file (YAML); required unless --resume");
  run->add_option("-o,--out", options->out_dir,
                  "output folder (created if missing); required unless --resume");
  run->add_option("--dt", options->h, "time step h in s (overrides the scene's h)")
      ->check(FinitePositive("--dt", engine::kTimeRange));
  run->add_option("--duration", options->duration, "simulated time in s (overrides the scene's)")
      ->check(FinitePositive("--duration", engine::kTimeRange));
  run->add_option("--set", options->overrides,
                  "override a scene value, key=value with a dotted key, e.g. bodies.0.mass=3 "
                  "(repeatable)");
  run->add_option("--model", options->model,
                  "contact model: auto (default: per body and step the cheapest model whose "
                  "answer is the hull model's: free flight, planar or hull), hull (the paper's), "
                  "planar (sliding only; stops "
                  "with exit code 5 where it does not apply) or multipatch (one ECP per convex "
                  "part of each body's `parts`) or point (the usual practice: hull vertices near "
                  "the ground as contact points, polyhedral friction cone, one LCP per step)")
      ->check(CLI::IsMember({"auto", "hull", "planar", "multipatch", "point"}));
  run->add_flag("--frames", options->frames, "also render DIR/frames/frame_NNNNNN.png");
  run->add_flag("--video", options->video,
                "also render DIR/video.mp4 (H.264; needs the ffmpeg program), with PNG frames "
                "only if --frames is given too");
  run->add_option("--fps", options->fps, "frames per simulated second (default 30)")
      ->check(FinitePositive("--fps", engine::kMagnitudeRange));
  run->add_option("--width", options->width, "frame width in pixels (default 1280)")
      ->check(IntegerInRange("--width", engine::kMinFramePixels, engine::kMaxFramePixels));
  run->add_option("--height", options->height, "frame height in pixels (default 720)")
      ->check(IntegerInRange("--height", engine::kMinFramePixels, engine::kMaxFramePixels));
  run->add_option("--resume", options->resume,
                  "continue the run in DIR that stopped early (Ctrl-C, SIGTERM, a solver "
                  "failure) from its checkpoint.json, with the scene and settings it began with; "
                  "the result is the same as a run that never stopped")
      ->type_name("DIR");
  run->add_option("--threads", options->threads,
                  "threads that solve a step's contact islands side by side (default: every "
                  "core); the result is the same, bit for bit, for any number")
      ->capture_default_str()
      ->check(IntegerInRange("--threads", 1, kMaxThreads));

  run->callback([options] {
    if (!options->resume.empty()) {
      Resume(*options);
      return;
    }
    if (options->scene.empty()) throw CLI::RequiredError("scene");
    if (options->out_dir.empty()) throw CLI::RequiredError("-o,--out");
    const std::vector<std::string> overrides = Overrides(*options);
    const engine::LoadedScene loaded = engine::LoadScene(options->scene, overrides);
    PrintWarnings(loaded);
    RunAndReport(loaded, options->out_dir,
                 RunArguments(options->scene, overrides, options->frames, options->video),
                 options->threads);
  });
}

void AddDropCommand(CLI::App& app) {
  auto options = std::make_shared<engine::DropOptions>();
  auto out_dir = std::make_shared<std::string>();
  auto frames = std::make_shared<bool>(false);
  auto video = std::make_shared<bool>(false);
  CLI::App* drop =
      app.add_subcommand("drop",
                         "Drop a mesh onto the ground z = 0 (mu = 0.22, e = 1, 1, 0.1 m); writes "
                         "DIR/trajectory.csv and DIR/summary.json");
  drop->add_option("mesh", options->mesh, "mesh file (any format assimp reads)")->required();
  drop->add_option("-o,--out", *out_dir, "output folder (created if missing)")->required();
  drop->add_option("--height", options->height,
                   "m, of the hull's lowest point above the ground at t = 0")
      ->capture_default_str()
      ->check(FiniteNumber("--height"));
  drop->add_option("--tilt", options->tilt_deg, "initial rotation about x, degrees")
      ->capture_default_str()
      ->check(FiniteNumber("--tilt"));
  drop->add_option("--spin", options->spin, "initial angular velocity about z, rad/s")
      ->capture_default_str()
      ->check(FiniteNumber("--spin"));
  drop->add_option("--duration", options->duration, "simulated time, s")
      ->capture_default_str()
      ->check(FinitePositive("--duration", engine::kTimeRange));
  drop->add_option("--dt", options->h, "time step, s")
      ->capture_default_str()
      ->check(FinitePositive("--dt", engine::kTimeRange));
  drop->add_option("--mass", options->mass, "kg (default: density 1000 kg/m^3)")
      ->check(FinitePositive("--mass", engine::kMassRange));
  drop->add_option("--scale", options->scale, "mesh units to m, e.g. 0.001 for mm (default 1)")
      ->check(FinitePositive("--scale", engine::kMeshScaleRange));
  drop->add_option("--units", options->units,
                   "the mesh's unit: mm, cm, m or in (the readable --scale; both must agree)")
      ->check(KnownUnit("--units"));
  drop->add_flag("--frames", *frames, "also render DIR/frames/frame_NNNNNN.png");
  drop->add_flag("--video", *video,
                 "also render DIR/video.mp4 (needs the ffmpeg program), with PNG frames only if "
                 "--frames is given too");
  drop->callback([options, out_dir, frames, video] {
    const engine::LoadedScene loaded = engine::MakeDropScene(*options);
    PrintWarnings(loaded);
    RunAndReport(loaded, *out_dir, DropArguments(*options, *frames, *video), /*threads=*/1);
  });
}

}  // namespace ecpsim::app
