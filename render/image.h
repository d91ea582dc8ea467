#pragma once
// An 8-bit RGB image in memory, top row first: what the renderer produces and PNG files hold.
// Frames bound for a video alone may hold B, G, R instead (ChannelOrder::kBgr, see renderer.h).

#include <cstdint>
#include <vector>

namespace ecpsim::render {

/// The order of a pixel's 3 bytes. kBgr is what ffmpeg converts to yuv420p fastest (swscale's
/// unscaled bgr24 path, ~1 ms against ~3 ms for rgb24 per 1280×720 frame; docs/rendering.md):
/// the renderer reads it back at no extra cost for frames that go only into a video.
enum class ChannelOrder { kRgb, kBgr };

/// `width` × `height` pixels, 3 bytes (R, G, B) each, rows stored top row first (row 0 is the top
/// of the picture, as in PNG files and raw video frames); B, G, R with ChannelOrder::kBgr (only
/// FfmpegPipe takes those).
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3 bytes, in `order`
  ChannelOrder order = ChannelOrder::kRgb;

  const std::uint8_t* Pixel(int x, int y) const { return pixels.data() + 3 * (y * width + x); }
  std::uint8_t* Pixel(int x, int y) { return pixels.data() + 3 * (y * width + x); }
};

}  // namespace ecpsim::render
