#include "app/frame_recorder.h"

#include <filesystem>

#include <fmt/format.h>

#include "common/errors.h"
#include "render/png_writer.h"

namespace ecpsim::app {

namespace fs = std::filesystem;

render::RenderSettings RenderSettingsFor(const engine::Scene& scene) {
  render::RenderSettings settings;
  settings.width = scene.output.width;
  settings.height = scene.output.height;
  return settings;
}

void ApplyCamera(const engine::Scene& scene, render::FrameInput& frame) {
  frame.title = fs::path(scene.source).filename().string();
  if (!scene.output.camera_fixed) return;
  frame.camera.automatic = false;
  frame.camera.position = scene.output.camera_position;
  frame.camera.target = scene.output.camera_target;
  frame.camera.fov_y_deg = scene.output.camera_fov_deg;
}

int FramesUpTo(const engine::Scene& scene, double t) {
  int frames = 0;
  while (frames / scene.output.fps <= t + scene.h / 2) ++frames;
  return frames;
}

FrameRecorder::FrameRecorder(const engine::Scene& scene, const std::string& out_dir, bool video,
                             const engine::State* resumed_from)
    : scene_(scene),
      builder_(scene),
      renderer_(RenderSettingsFor(scene)),
      png_((fs::path(out_dir) / "frames").string(), 1, 4, render::kFastPngCompression,
           resumed_from ? FramesUpTo(scene, resumed_from->t) : 0),
      frames_(resumed_from ? FramesUpTo(scene, resumed_from->t) : 0) {
  if (!video) return;
  try {
    video_ = std::make_unique<render::FfmpegPipe>((fs::path(out_dir) / "video.mp4").string(),
                                                  scene.output.width, scene.output.height,
                                                  scene.output.fps);
  } catch (const InputError& e) {
    video_error_ = e.what();
    return;
  }
  // a resumed video starts with the frames of the run's earlier part
  for (int k = 0; k < frames_; ++k) {
    const render::Image frame = render::ReadPng(png_.FramePath(k));
    if (frame.width != scene.output.width || frame.height != scene.output.height) {
      throw InputError(fmt::format("{}: {}x{} pixels; expected the run's {}x{} frames",
                                   png_.FramePath(k), frame.width, frame.height,
                                   scene.output.width, scene.output.height));
    }
    video_->Write(frame);
  }
}

void FrameRecorder::Observe(const engine::State& state, const engine::StepReport& report) {
  // frame k shows the state nearest to t = k / fps (FramesUpTo)
  while (frames_ / scene_.output.fps <= state.t + scene_.h / 2) {
    render::FrameInput frame = builder_.Build(state, report.iterations, report.models);
    ApplyCamera(scene_, frame);
    render::Image image = renderer_.Render(frame);
    if (video_) video_->Write(image);
    png_.Add(std::move(image));
    ++frames_;
  }
}

void FrameRecorder::Finish() {
  png_.Finish();
  if (video_) video_->Finish();
  if (video_error_) {
    throw InputError(*video_error_ + fmt::format(" (the {} PNG frames are written)", frames_));
  }
}

}  // namespace ecpsim::app
