#pragma once
// Image comparison for regression tests: a per-channel threshold plus a bound on the fraction of
// pixels beyond it, with a diff image that shows where they differ.

#include <string>

#include "render/image.h"

namespace ecpsim::render {

/// Two images match if at most `max_fraction` of the pixels have some channel differing by more
/// than `channel_threshold` (0–255). The defaults tolerate anti-aliasing noise on edges (a few
/// coverage samples flipping on a different CPU or Mesa build) and catch a marker moved by 2 pixels
/// in a 320×240 frame; see docs/rendering.md for the numbers.
struct CompareTolerance {
  int channel_threshold = 24;    // levels of 255
  double max_fraction = 0.0005;  // of all pixels
};

struct ImageComparison {
  bool same_size = false;
  long total_pixels = 0;
  long differing_pixels = 0;       // pixels with a channel difference > channel_threshold
  double differing_fraction = 1;   // differing_pixels / total_pixels (1 for different sizes)
  int max_channel_difference = 0;  // over all pixels and channels
  bool match = false;              // same size and differing_fraction ≤ max_fraction
  /// Same size as the inputs: the expected image faded to grey, pixels over the threshold in red,
  /// pixels differing within the threshold in orange. Empty for different sizes.
  Image diff;

  /// One line, e.g. "412 of 76800 pixels (0.536%) differ by more than 24 levels (max 255); limit
  /// 0.05%".
  std::string Summary(const CompareTolerance& tolerance) const;
};

/// Compares `actual` against `expected`.
/// @throws InputError if the tolerance is out of range (threshold outside 0..255, fraction outside
///         [0, 1] or not finite) or an image's buffer does not match its size.
ImageComparison CompareImages(const Image& expected, const Image& actual,
                              const CompareTolerance& tolerance = {});

}  // namespace ecpsim::render
