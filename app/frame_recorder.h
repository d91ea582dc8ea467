#pragma once
// Frames of a running simulation at a fixed frame rate: PNGs in DIR/frames, an MP4, or both.

#include <memory>
#include <optional>
#include <string>

#include "engine/scene_io/loaded_scene.h"
#include "engine/state.h"
#include "render/ffmpeg_pipe.h"
#include "render/frame_input.h"
#include "render/png_sequence_writer.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace ecpsim::app {

/// The size the scene's `output` block asks for.
render::RenderSettings RenderSettingsFor(const engine::OutputSettings& output);
/// The camera the scene's `output` block asks for, and the scene file's name as the title.
void ApplyCamera(const engine::LoadedScene& loaded, render::FrameInput& frame);

/// How many frames a run has rendered once it has reached the state at `t` (frame k shows the
/// state nearest to k / fps).
int FramesUpTo(const engine::LoadedScene& loaded, double t);

/// What a run records: PNG frames (`--frames`), a video (`--video`), or both.
struct FrameOutputs {
  bool frames = false;  // DIR/frames/frame_NNNNNN.png
  bool video = false;   // DIR/video.mp4
};

/// Renders the state nearest to each frame time k / fps (fps from the output settings, independent
/// of h) into DIR/frames/frame_NNNNNN.png — PNG encoding on a worker thread while the next frame
/// renders — and/or into DIR/video.mp4 through the ffmpeg program. A video alone is rendered
/// straight into ffmpeg, in B, G, R byte order (ffmpeg's cheapest conversion to yuv420p), and
/// downsampled on the pipe's writer thread while the next frame draws: no PNG is encoded and
/// DIR/frames is not made.
class FrameRecorder {
 public:
  /// With `resumed_from` (the state a resumed run continues from, app/checkpoint.h) the frames up
  /// to that state are taken as rendered already: numbering goes on after them. With PNG frames
  /// the video is encoded again, fed the earlier frames from DIR/frames first; a video alone is
  /// continued: DIR/video.mp4 must hold exactly the earlier frames, and the new ones are encoded
  /// as a second segment joined to it losslessly when finished (render/ffmpeg_pipe.h).
  /// @throws InputError if DIR/frames cannot be created, or a frame the resumed video needs is
  ///         missing (DIR/frames/frame_NNNNNN.png, or frames of a video alone: naming the counts).
  ///         A missing ffmpeg does not stop a run with PNG frames: they are still written and
  ///         Finish() reports it; for a video alone it is an InputError here.
  FrameRecorder(const engine::LoadedScene& loaded, const std::string& out_dir, FrameOutputs outputs,
                const engine::State* resumed_from = nullptr);

  /// Called with the initial state and after every step (StepObserver).
  void Observe(const engine::State& state, const engine::StepReport& report);

  /// Waits for the PNG encoder and closes the video (with every frame rendered so far, also after
  /// an interrupt or a failure).
  /// @throws InputError if ffmpeg was missing (the frames are written), std::runtime_error if
  ///         an encoder failed.
  void Finish();

  int frames() const { return frames_; }

 private:
  const engine::LoadedScene& loaded_;  // outlives the recorder
  render::SceneFrameBuilder builder_;
  render::Renderer renderer_;
  std::optional<render::PngSequenceWriter> png_;  // with PNG frames
  std::unique_ptr<render::FfmpegPipe> video_;
  std::optional<std::string> video_error_;
  int frames_ = 0;  // rendered by the run, its earlier parts included
};

}  // namespace ecpsim::app
