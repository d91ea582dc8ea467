#pragma once
// An 8-bit RGB image in memory, top row first: what the renderer produces and PNG files hold.

#include <cstdint>
#include <vector>

namespace ecpsim::render {

/// `width` × `height` pixels, 3 bytes (R, G, B) each, rows stored top row first (row 0 is the top
/// of the picture, as in PNG files and raw video frames).
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3 bytes

  const std::uint8_t* Pixel(int x, int y) const { return rgb.data() + 3 * (y * width + x); }
  std::uint8_t* Pixel(int x, int y) { return rgb.data() + 3 * (y * width + x); }
};

}  // namespace ecpsim::render
