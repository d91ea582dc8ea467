#include "app/frame_recorder.h"

#include <filesystem>
#include <utility>

#include <fmt/format.h>

#include "common/errors.h"
#include "render/frame_times.h"
#include "render/png_writer.h"

namespace ecpsim::app {

namespace fs = std::filesystem;

render::RenderSettings RenderSettingsFor(const engine::OutputSettings& output) {
  render::RenderSettings settings;
  settings.width = output.width;
  settings.height = output.height;
  return settings;
}

void ApplyCamera(const engine::LoadedScene& loaded, render::FrameInput& frame) {
  frame.title = fs::path(loaded.scene.source).filename().string();
  const engine::OutputSettings& output = loaded.output;
  if (!output.camera_fixed) return;
  frame.camera.automatic = false;
  frame.camera.position = output.camera_position;
  frame.camera.target = output.camera_target;
  frame.camera.fov_y_deg = output.camera_fov_deg;
}

namespace {

// a video alone takes the frames in the byte order ffmpeg converts fastest
render::RenderSettings RecorderSettings(const engine::OutputSettings& output,
                                        FrameOutputs outputs) {
  render::RenderSettings settings = RenderSettingsFor(output);
  if (!outputs.frames) settings.channel_order = render::ChannelOrder::kBgr;
  return settings;
}

}  // namespace

int FramesUpTo(const engine::LoadedScene& loaded, double t) {
  return render::FramesDue(loaded.output.fps, loaded.scene.h, t);
}

FrameRecorder::FrameRecorder(const engine::LoadedScene& loaded, const std::string& out_dir,
                             FrameOutputs outputs, const engine::State* resumed_from)
    : loaded_(loaded),
      builder_(loaded.scene),
      renderer_(RecorderSettings(loaded.output, outputs)),
      frames_(resumed_from ? FramesUpTo(loaded, resumed_from->t) : 0) {
  ECPSIM_DEMAND(outputs.frames || outputs.video);
  if (outputs.frames) {
    png_.emplace((fs::path(out_dir) / "frames").string(), 1, 4, render::kFastPngCompression,
                 frames_);
  }
  if (!outputs.video) return;
  const std::string video_path = (fs::path(out_dir) / "video.mp4").string();
  const engine::OutputSettings& output = loaded.output;
  const int width = output.width, height = output.height;
  if (!png_) {
    // a video alone: a resumed run continues the one there, which holds the earlier frames
    if (frames_ > 0) {
      const bool there = fs::is_regular_file(video_path);
      const int earlier = there ? render::CountVideoFrames(video_path) : 0;
      if (earlier != frames_) {
        throw InputError(
            fmt::format("{}: {}; the run to resume rendered {} frames up to t = {} "
                        "s, so the video cannot be continued: start the run again",
                        video_path, there ? fmt::format("{} frames", earlier) : "missing", frames_,
                        resumed_from->t));
      }
    }
    video_ = std::make_unique<render::FfmpegPipe>(
        video_path, width, height, output.fps, "ffmpeg",
        frames_ > 0 ? render::VideoStart::kAppend : render::VideoStart::kReplace,
        renderer_.settings().channel_order);
    return;
  }
  try {
    video_ = std::make_unique<render::FfmpegPipe>(video_path, width, height, output.fps);
  } catch (const InputError& e) {
    video_error_ = e.what();
    return;
  }
  // a resumed video starts with the frames of the run's earlier part
  for (int k = 0; k < frames_; ++k) {
    render::Image frame = render::ReadPng(png_->FramePath(k));
    if (frame.width != width || frame.height != height) {
      throw InputError(fmt::format("{}: {}x{} pixels; expected the run's {}x{} frames",
                                   png_->FramePath(k), frame.width, frame.height, width, height));
    }
    video_->Write(std::move(frame));
  }
}

void FrameRecorder::Observe(const engine::State& state, const engine::StepReport& report) {
  // frame k shows the state nearest to t = k / fps (render/frame_times.h)
  while (render::FrameDue(frames_, loaded_.output.fps, loaded_.scene.h, state.t)) {
    render::FrameInput frame = builder_.Build(state, report.iterations, report.models);
    ApplyCamera(loaded_, frame);
    if (png_) {
      render::Image image = renderer_.Render(frame);
      if (video_) video_->Write(image);
      png_->Add(std::move(image));
    } else {
      // a video alone: ffmpeg's writer thread downsamples while the next frame draws
      video_->Write(renderer_.RenderDrawing(frame, video_->SpareDrawing()));
    }
    ++frames_;
  }
}

void FrameRecorder::Finish() {
  if (png_) png_->Finish();
  if (video_) video_->Finish();
  if (video_error_) {
    throw InputError(*video_error_ + fmt::format(" (the {} PNG frames are written)", frames_));
  }
}

}  // namespace ecpsim::app
