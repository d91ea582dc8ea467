#pragma once
// An offscreen framebuffer with anti-aliasing (supersampling or MSAA), read back as an Image.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "render/image.h"

namespace ecpsim::render {

/// A frame as read back, before its supersamples are averaged: drawing_width × drawing_height
/// pixels of 4 bytes (R, G, B, A; B, G, R, A with ChannelOrder::kBgr), bottom row first.
/// Downsample() turns it into the Image; it needs no OpenGL context, so another thread can do it
/// while the next frame draws.
struct Drawing {
  int width = 0, height = 0;                  // of the image it makes, pixels
  int drawing_width = 0, drawing_height = 0;  // pixels
  double supersample = 1;
  ChannelOrder order = ChannelOrder::kRgb;
  std::unique_ptr<std::uint8_t[]> rgba;  // left uninitialized before the read: zeroing costs
};

/// The image of `drawing` (top row first, channels in its order): each pixel the mean of its
/// footprint's drawing pixels, as RenderTarget describes.
Image Downsample(const Drawing& drawing);

/// RGBA8 colour + 24-bit depth + 8-bit stencil for an image of `width` × `height` pixels, with
/// two kinds of anti-aliasing:
/// - supersampling: drawing happens at `supersample` × the image size (1, 1.5, 2, 3 or 4) and
///   Read() box-filters each image pixel's footprint on the CPU: the mean of its S × S block for
///   integer S; for 1.5, each 2 × 2 image block covers a 3 × 3 drawing block and each image
///   pixel is the area-weighted mean of the 2 × 2 drawing pixels it overlaps (weights 4, 2, 2, 1
///   ninths). On llvmpipe this is the fast way: 2×2 supersampling costs ~3× a plain frame where
///   4× MSAA costs more, because Mesa's multisample clear and resolve blit dominate;
/// - `samples` > 1: multisampling, resolved with glBlitFramebuffer (cheap on real GPUs).
/// Needs a current GlContext for its whole life.
class RenderTarget {
 public:
  /// @throws std::runtime_error if the size or sample count is not supported by the context
  ///         (the message gives both and the limits).
  /// @throws std::runtime_error also for a `supersample` other than 1, 1.5, 2, 3 or 4.
  /// Read() returns images in `order` (ChannelOrder::kBgr: read back as BGRA, same cost).
  RenderTarget(int width, int height, int samples, double supersample = 1,
               ChannelOrder order = ChannelOrder::kRgb);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  /// The drawing size: the image size × supersample, rounded up (an odd image side at 1.5 has a
  /// last image pixel made of one and a half drawing pixels). Drawing coordinates are in these
  /// pixels.
  int width() const { return draw_width_; }
  int height() const { return draw_height_; }
  int image_width() const { return width_; }
  int image_height() const { return height_; }
  int samples() const { return samples_; }
  double supersample() const { return supersample_; }

  /// Binds the drawing framebuffer and sets the viewport to all of it.
  void Bind() const;
  /// The drawing framebuffer object (GL name), e.g. to copy its buffers.
  unsigned framebuffer() const { return draw_fbo_; }

  /// Fills the whole image with `rgba` (components in [0, 1]) and clears depth and stencil.
  void Clear(const std::array<float, 4>& rgba) const;

  /// Fills the rectangle of `w` × `h` drawing pixels whose top-left pixel is (x, y) (y down, row 0
  /// at the top, as in Image) with `rgba`, and clears its depth and stencil.
  void ClearRect(int x, int y, int w, int h, const std::array<float, 4>& rgba) const;

  /// Resolves the samples, reads the pixels back and averages the supersamples; top row first,
  /// channels in the order given at construction.
  Image Read() const;

  /// Resolves the samples and reads the pixels back, leaving the average to Downsample (on any
  /// thread): Downsample(ReadDrawing()) equals Read(). The bytes go into `spare`'s buffer if it
  /// has one of this size: a fresh 8 MB buffer per frame costs ~2 ms of page faults.
  Drawing ReadDrawing(Drawing spare = {}) const;

 private:
  int width_, height_, samples_;
  double supersample_;
  ChannelOrder order_;
  int draw_width_, draw_height_;
  void ReadInto(std::uint8_t* rgba) const;

  mutable std::vector<std::uint8_t> readback_;  // reused: zeroing 15 MB per frame costs ~2 ms
  unsigned draw_fbo_ = 0, draw_color_ = 0, draw_depth_ = 0;
  unsigned resolve_fbo_ = 0, resolve_color_ = 0;
};

}  // namespace ecpsim::render
