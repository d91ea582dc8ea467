// Frames per second of render + PNG (and + MP4), and of render + MP4 without PNG, at 1280×720
// and 1920×1080, for the desk and a 100k-triangle mesh. Meshes stay in GPU buffers across frames;
// PNGs encode on a worker thread, frames go to ffmpeg on another (counter ffmpeg_cpu_ms: the
// encoder process's CPU per frame, which cpu_ms leaves out).
// Run: build/bench/ecpsim_bench_render --benchmark_repetitions=5 --benchmark_report_aggregates_only
// (ECPSIM_BENCH_SUPERSAMPLE=2 measures 2×2 supersampling instead of the default 1.5×).
// BM_RenderParts renders with parts of the scene left out, to attribute a frame's CPU to passes.
// The frames are static, so from the third frame on the ground is copied from the background
// cache (as with a scene's fixed output.camera); BM_RenderPngMovingCamera measures the frames of
// a camera that moves every frame, which draw it.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <sys/resource.h>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "render/ffmpeg_pipe.h"
#include "render/png_sequence_writer.h"
#include "render/renderer.h"
#include "tests/render/canonical_frames.h"

namespace ecpsim::render {
namespace {

constexpr int kDesk = 0, kTorus = 1;

// a torus of 250 × 200 quads = 100 000 triangles (R = 0.3 m, r = 0.08 m) lying on the ground
geometry::TriangleMesh MakeTorusMesh(int around, int tube) {
  geometry::TriangleMesh mesh;
  const double R = 0.3, r = 0.08;
  for (int i = 0; i < around; ++i) {
    const double u = 2 * M_PI * i / around;
    for (int j = 0; j < tube; ++j) {
      const double v = 2 * M_PI * j / tube;
      mesh.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u),
                                 (R + r * std::cos(v)) * std::sin(u), r + r * std::sin(v));
    }
  }
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      const int a = i * tube + j, b = ((i + 1) % around) * tube + j;
      const int c = ((i + 1) % around) * tube + (j + 1) % tube, d = i * tube + (j + 1) % tube;
      mesh.triangles.emplace_back(a, b, c);
      mesh.triangles.emplace_back(a, c, d);
    }
  }
  return mesh;
}

const FrameInput& Frame(int scene) {
  static const FrameInput desk = testing::DeskRestingFlat();
  static const FrameInput torus = [] {
    FrameInput frame = testing::GroundFrame();
    frame.title = "torus, 100k triangles";
    frame.bodies.push_back(
        testing::MakeBody(MakeTorusMesh(250, 200), Eigen::Isometry3d::Identity()));
    frame.contacts.push_back(testing::GroundContact(frame.bodies[0]));
    return frame;
  }();
  return scene == kDesk ? desk : torus;
}

std::string OutputDir(const std::string& name) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / "ecpsim_render_bench" / name).string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

RenderSettings Settings(const benchmark::State& state) {
  RenderSettings settings;
  settings.width = static_cast<int>(state.range(1));
  settings.height = static_cast<int>(state.range(2));
  // the default anti-aliasing (1.5× supersampling); ECPSIM_BENCH_SUPERSAMPLE picks another
  if (const char* factor = std::getenv("ECPSIM_BENCH_SUPERSAMPLE")) {
    settings.supersample = std::atof(factor);
  }
  return settings;
}

// CPU seconds of the whole process (every llvmpipe thread and the PNG workers): on a shared
// machine wall time follows the load, CPU per frame much less. RUSAGE_CHILDREN: of the ended
// child processes (ffmpeg, once Finish has waited for it)
double ProcessCpuSeconds(int who = RUSAGE_SELF) {
  rusage usage{};
  getrusage(who, &usage);
  const auto seconds = [](const timeval& t) { return t.tv_sec + 1e-6 * t.tv_usec; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// counter cpu_ms: process CPU per frame (ms, every thread)
void CountCpu(benchmark::State& state, double cpu_start) {
  const auto frames = std::max<benchmark::IterationCount>(1, state.iterations());
  state.counters["cpu_ms"] = 1e3 * (ProcessCpuSeconds() - cpu_start) / static_cast<double>(frames);
}

// counter ffmpeg_cpu_ms: the encoder process's CPU per frame (ms, start and flush included)
void CountFfmpegCpu(benchmark::State& state, double children_start) {
  const auto frames = std::max<benchmark::IterationCount>(1, state.iterations());
  state.counters["ffmpeg_cpu_ms"] =
      1e3 * (ProcessCpuSeconds(RUSAGE_CHILDREN) - children_start) / static_cast<double>(frames);
}

void Label(benchmark::State& state, const char* what, double cpu_start) {
  state.SetLabel(fmt::format("{} {} {}x{} SSAA {}x", what,
                             state.range(0) == kDesk ? "desk" : "torus100k", state.range(1),
                             state.range(2), Settings(state).supersample));
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  CountCpu(state, cpu_start);
}

// rendering alone (draw + MSAA resolve + read-back)
void BM_Render(benchmark::State& state) {
  Renderer renderer(Settings(state));
  const FrameInput& frame = Frame(static_cast<int>(state.range(0)));
  renderer.Render(frame);  // warm-up: shaders, GPU buffers
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) benchmark::DoNotOptimize(renderer.Render(frame));
  Label(state, "render", cpu_start);
}

// render + PNG (zlib level 1) on a worker thread: the `--frames` pipeline
void BM_RenderPng(benchmark::State& state) {
  Renderer renderer(Settings(state));
  const FrameInput& frame = Frame(static_cast<int>(state.range(0)));
  renderer.Render(frame);
  PngSequenceWriter writer(OutputDir("png"), 1, 2);
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) writer.Add(renderer.Render(frame));
  writer.Finish();
  Label(state, "render+png", cpu_start);
}

// render + PNG with a camera that moves every frame (an automatic camera following moving
// bodies): the ground is drawn every frame instead of being copied from the background cache
void BM_RenderPngMovingCamera(benchmark::State& state) {
  Renderer renderer(Settings(state));
  FrameInput frame = Frame(static_cast<int>(state.range(0)));
  // the automatic camera's view, as a fixed camera that is then nudged by ±1 mm per frame
  const Camera camera = renderer.FrameCamera(frame);
  frame.camera.automatic = false;
  frame.camera.position = camera.eye;
  frame.camera.target = camera.target;
  renderer.Render(frame);
  PngSequenceWriter writer(OutputDir("png_moving"), 1, 2);
  const double cpu_start = ProcessCpuSeconds();
  long index = 0;
  for (auto _ : state) {
    frame.camera.position.x() = camera.eye.x() + (index++ % 2 == 0 ? 1e-3 : -1e-3);
    writer.Add(renderer.Render(frame));
    if (renderer.LastBackgroundCached()) state.SkipWithError("the background was cached");
  }
  writer.Finish();
  Label(state, "render+png, moving camera", cpu_start);
}

// render + PNG + H.264 through ffmpeg: the `--frames --video` pipeline
void BM_RenderPngVideo(benchmark::State& state) {
  const RenderSettings settings = Settings(state);
  Renderer renderer(settings);
  const FrameInput& frame = Frame(static_cast<int>(state.range(0)));
  renderer.Render(frame);
  const std::string dir = OutputDir("video");
  PngSequenceWriter writer(dir + "/frames", 1, 2);
  const double children_start = ProcessCpuSeconds(RUSAGE_CHILDREN);
  FfmpegPipe video(dir + "/video.mp4", settings.width, settings.height, 30);
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) {
    Image image = renderer.Render(frame);
    video.Write(image);
    writer.Add(std::move(image));
  }
  writer.Finish();
  video.Finish();
  Label(state, "render+png+mp4", cpu_start);
  CountFfmpegCpu(state, children_start);
}

// render + H.264 through ffmpeg, no PNG: the `--video` pipeline (a run that asks for a video only,
// as app/frame_recorder does it: B, G, R frames, downsampled on the pipe's writer thread)
void BM_RenderVideo(benchmark::State& state) {
  RenderSettings settings = Settings(state);
  settings.channel_order = ChannelOrder::kBgr;
  Renderer renderer(settings);
  const FrameInput& frame = Frame(static_cast<int>(state.range(0)));
  renderer.Render(frame);
  const double children_start = ProcessCpuSeconds(RUSAGE_CHILDREN);
  FfmpegPipe video(OutputDir("video_only") + "/video.mp4", settings.width, settings.height, 30,
                   "ffmpeg", VideoStart::kReplace, settings.channel_order);
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) video.Write(renderer.RenderDrawing(frame, video.SpareDrawing()));
  video.Finish();
  Label(state, "render+mp4", cpu_start);
  CountFfmpegCpu(state, children_start);
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (int scene : {kDesk, kTorus}) {
    b->Args({scene, 1280, 720});
    b->Args({scene, 1920, 1080});
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
}

// what a pass costs: render alone, 1280×720, with parts of the scene removed; the counter
// cpu_ms (process CPU per frame) against the full scene's gives the part's cost
enum Part { kFull, kNoPlanes, kNoHulls, kNoContacts, kPlanesOnly, kEmpty, kEmptyNoText };

void BM_RenderParts(benchmark::State& state) {
  RenderSettings settings;
  settings.width = 1280;
  settings.height = 720;
  Renderer renderer(settings);
  FrameInput frame = Frame(static_cast<int>(state.range(0)));
  const auto part = static_cast<Part>(state.range(1));
  if (part == kNoPlanes || part == kEmpty || part == kEmptyNoText) frame.planes.clear();
  if (part == kNoHulls) frame.show.hull = false;
  if (part >= kNoContacts) frame.contacts.clear();
  if (part >= kPlanesOnly) frame.bodies.clear();
  if (part == kEmptyNoText) {
    frame.show.text = false;
    frame.show.inset = false;
    frame.title.clear();
  }
  renderer.Render(frame);
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) benchmark::DoNotOptimize(renderer.Render(frame));
  static const char* const kNames[] = {"full",        "no planes", "no hulls",      "no contacts",
                                       "planes only", "empty",     "empty, no text"};
  state.SetLabel(
      fmt::format("{} {}", state.range(0) == kDesk ? "desk" : "torus100k", kNames[part]));
  CountCpu(state, cpu_start);
}

BENCHMARK(BM_Render)->Apply(Sizes);
BENCHMARK(BM_RenderPng)->Apply(Sizes);
BENCHMARK(BM_RenderPngVideo)->Apply(Sizes);
BENCHMARK(BM_RenderVideo)->Apply(Sizes);
BENCHMARK(BM_RenderPngMovingCamera)
    ->Args({kDesk, 1280, 720})
    ->Args({kTorus, 1280, 720})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(BM_RenderParts)
    ->ArgsProduct({{kDesk, kTorus}, benchmark::CreateDenseRange(kFull, kEmptyNoText, 1)})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

}  // namespace
}  // namespace ecpsim::render
