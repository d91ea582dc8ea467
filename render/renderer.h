#pragma once
// The offscreen renderer: turns a FrameInput into an Image (bodies, hulls, contact patches, ECPs,
// inset and text), with meshes kept in GPU buffers across frames.

#include <memory>
#include <string>

#include "render/camera.h"
#include "render/font_atlas.h"
#include "render/frame_input.h"
#include "render/image.h"
#include "render/render_target.h"

namespace ecpsim::render {

struct RenderSettings {
  int width = 1280;  // pixels
  int height = 720;  // pixels
  // anti-aliasing by drawing at this multiple of the width and height and box-filtering down:
  // 1 (off), 1.5, 2, 3 or 4. 1.5 (2.25 drawing pixels per image pixel) is the default: on
  // llvmpipe it costs ~0.6× the fill of 2 and keeps edges smooth (see docs/rendering.md)
  double supersample = 1.5;
  int samples = 1;  // MSAA samples per drawing pixel (1 = off; slow on llvmpipe)
  // the byte order of the rendered images: kBgr for frames that go only into a video (ffmpeg
  // converts bgr24 to yuv420p ~3× faster than rgb24); the pixels are the same either way
  ChannelOrder channel_order = ChannelOrder::kRgb;
  std::string font_path = kDefaultFontPath;
};

/// Owns an OpenGL context and everything on it; render frames of one size with it. Output is a
/// deterministic function of the FrameInput on a given machine and Mesa build. Not thread-safe:
/// construct, use and destroy on one thread.
class Renderer {
 public:
  /// @throws InputError for a size outside 16..8192 pixels, supersample not 1, 1.5, 2, 3 or
  ///         4, samples outside 1..16, or a missing font; std::runtime_error if no OpenGL
  ///         context can be made.
  explicit Renderer(const RenderSettings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws one frame.
  /// @throws InputError for non-finite poses, points or camera values in `frame`.
  Image Render(const FrameInput& frame);

  /// Draws one frame and reads it back without averaging the supersamples: Downsample() of the
  /// result equals Render(frame) and can run on another thread (no OpenGL) while the next frame
  /// draws (FfmpegPipe does, for a video alone). `spare`: an earlier frame's Drawing whose
  /// buffer is reused (RenderTarget::ReadDrawing).
  /// @throws InputError as Render.
  Drawing RenderDrawing(const FrameInput& frame, Drawing spare = {});

  /// The camera Render would use for `frame`, in image pixels (e.g. to find where a world point
  /// lands in the image).
  Camera FrameCamera(const FrameInput& frame);

  const RenderSettings& settings() const;
  /// "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6"
  std::string Description() const;
  /// Meshes currently held in GPU buffers.
  int CachedMeshCount() const;
  /// Whether the last Render copied a saved background (the clear and the ground) instead of
  /// drawing it: the camera and the planes were the same as in the two frames before (a fixed
  /// camera; see docs/rendering.md). The pixels are the same either way.
  bool LastBackgroundCached() const;

 private:
  void Draw(const FrameInput& frame);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ecpsim::render
