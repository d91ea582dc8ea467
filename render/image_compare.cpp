#include "render/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

void CheckBuffer(const Image& image, const char* which) {
  if (image.width < 0 || image.height < 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height * 3) {
    throw InputError(fmt::format("{} image {}x{} holds {} bytes: expected width × height × 3",
                                 which, image.width, image.height, image.pixels.size()));
  }
}

}  // namespace

std::string ImageComparison::Summary(const CompareTolerance& tolerance) const {
  if (!same_size) return "the images differ in size";
  return fmt::format(
      "{} of {} pixels ({:.3f}%) differ by more than {} levels (max {}); limit {:g}%",
      differing_pixels, total_pixels, 100 * differing_fraction, tolerance.channel_threshold,
      max_channel_difference, 100 * tolerance.max_fraction);
}

ImageComparison CompareImages(const Image& expected, const Image& actual,
                              const CompareTolerance& tolerance) {
  if (tolerance.channel_threshold < 0 || tolerance.channel_threshold > 255) {
    throw InputError(
        fmt::format("threshold = {}: expected 0 to 255 levels", tolerance.channel_threshold));
  }
  if (!std::isfinite(tolerance.max_fraction) || tolerance.max_fraction < 0 ||
      tolerance.max_fraction > 1) {
    throw InputError(fmt::format("max fraction = {}: expected a fraction of pixels in [0, 1]",
                                 tolerance.max_fraction));
  }
  CheckBuffer(expected, "expected");
  CheckBuffer(actual, "actual");

  ImageComparison result;
  result.same_size = expected.width == actual.width && expected.height == actual.height;
  if (!result.same_size) return result;

  result.total_pixels = static_cast<long>(expected.width) * expected.height;
  result.diff = expected;
  for (long i = 0; i < result.total_pixels; ++i) {
    const std::uint8_t* e = expected.pixels.data() + 3 * i;
    const std::uint8_t* a = actual.pixels.data() + 3 * i;
    int difference = 0;
    for (int k = 0; k < 3; ++k) difference = std::max(difference, std::abs(int(e[k]) - int(a[k])));
    result.max_channel_difference = std::max(result.max_channel_difference, difference);

    // faded grey context, so the marked pixels stand out
    std::uint8_t* d = result.diff.pixels.data() + 3 * i;
    const int grey = 160 + (int(e[0]) + int(e[1]) + int(e[2])) / 9;
    d[0] = d[1] = d[2] = static_cast<std::uint8_t>(std::min(grey, 255));
    if (difference > tolerance.channel_threshold) {
      ++result.differing_pixels;
      d[0] = 230, d[1] = 0, d[2] = 0;
    } else if (difference > 0) {
      d[0] = 255, d[1] = 170, d[2] = 60;
    }
  }
  result.differing_fraction =
      result.total_pixels > 0 ? double(result.differing_pixels) / result.total_pixels : 0;
  result.match = result.differing_fraction <= tolerance.max_fraction;
  return result;
}

}  // namespace ecpsim::render
