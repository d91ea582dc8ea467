#pragma once
// Test helpers for videos: decode an MP4 to its frames with the ffmpeg program (independently of
// render/ffmpeg_pipe), and tell which of several images a decoded frame shows.

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "render/image.h"

namespace ecpsim::testing {

/// Every frame of the video at `path`, decoded to `width` × `height` RGB (the video's own size;
/// an even one, as yuv420p has it). Empty if ffmpeg fails or the bytes are not whole frames.
inline std::vector<render::Image> DecodeVideo(const std::string& path, int width, int height) {
  const std::string command =
      fmt::format("ffmpeg -v error -i '{}' -f rawvideo -pix_fmt rgb24 - 2>/dev/null", path);
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return {};
  std::vector<std::uint8_t> bytes;
  std::uint8_t buffer[65536];
  for (size_t n; (n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0;) {
    bytes.insert(bytes.end(), buffer, buffer + n);
  }
  const size_t frame_bytes = static_cast<size_t>(width) * height * 3;
  if (::pclose(pipe) != 0 || bytes.size() % frame_bytes != 0) return {};
  std::vector<render::Image> frames(bytes.size() / frame_bytes);
  for (size_t k = 0; k < frames.size(); ++k) {
    frames[k].width = width;
    frames[k].height = height;
    frames[k].pixels.assign(bytes.begin() + k * frame_bytes, bytes.begin() + (k + 1) * frame_bytes);
  }
  return frames;
}

/// Mean absolute difference of two images of one size, levels per channel (0 to 255).
inline double MeanLevelDifference(const render::Image& a, const render::Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(int{a.pixels[i]} - int{b.pixels[i]});
  return sum / static_cast<double>(a.pixels.size());
}

/// The index of the image in `candidates` nearest to `frame` (MeanLevelDifference).
inline int NearestImage(const render::Image& frame, const std::vector<render::Image>& candidates) {
  int nearest = -1;
  double least = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < candidates.size(); ++j) {
    const double difference = MeanLevelDifference(frame, candidates[j]);
    if (difference < least) {
      least = difference;
      nearest = static_cast<int>(j);
    }
  }
  return nearest;
}

}  // namespace ecpsim::testing
