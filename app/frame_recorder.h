#pragma once
// Frames of a running simulation at a fixed frame rate: PNGs in DIR/frames and optionally an MP4.

#include <memory>
#include <optional>
#include <string>

#include "engine/scene.h"
#include "engine/state.h"
#include "render/ffmpeg_pipe.h"
#include "render/frame_input.h"
#include "render/png_sequence_writer.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace ecpsim::app {

/// The camera, size and title the scene's `output` block asks for.
render::RenderSettings RenderSettingsFor(const engine::Scene& scene);
void ApplyCamera(const engine::Scene& scene, render::FrameInput& frame);

/// Renders the state nearest to each frame time k / fps (fps from scene.output, independent of
/// h) into DIR/frames/frame_NNNNNN.png — PNG encoding on a worker thread while the next frame
/// renders — and, with `video`, into DIR/video.mp4 through the ffmpeg program.
/// How many frames a run has rendered once it has reached the state at `t` (frame k shows the
/// state nearest to k / fps).
int FramesUpTo(const engine::Scene& scene, double t);

class FrameRecorder {
 public:
  /// With `resumed_from` (the state a resumed run continues from, app/checkpoint.h) the frames up
  /// to that state are taken as rendered already: numbering goes on after them, and the video is
  /// fed them back from DIR/frames first, so it shows the whole run.
  /// @throws InputError if DIR/frames cannot be created, or a frame the resumed video needs is
  ///         missing. A missing ffmpeg does not stop the run: the frames are still written and
  ///         Finish() reports it.
  FrameRecorder(const engine::Scene& scene, const std::string& out_dir, bool video,
                const engine::State* resumed_from = nullptr);

  /// Called with the initial state and after every step (StepObserver).
  void Observe(const engine::State& state, const engine::StepReport& report);

  /// Waits for the PNG encoder and closes the video.
  /// @throws InputError if ffmpeg was missing (the frames are written), std::runtime_error if
  ///         an encoder failed.
  void Finish();

  int frames() const { return frames_; }

 private:
  const engine::Scene& scene_;
  render::SceneFrameBuilder builder_;
  render::Renderer renderer_;
  render::PngSequenceWriter png_;
  std::unique_ptr<render::FfmpegPipe> video_;
  std::optional<std::string> video_error_;
  int frames_ = 0;
};

}  // namespace ecpsim::app
