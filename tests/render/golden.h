#pragma once
// Golden-image assertions: compare a frame with tests/golden/<name>.png; on a mismatch write the
// actual and diff images under the build tree and name them; ECPSIM_BLESS=1 rewrites the golden.

#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "render/image_compare.h"
#include "render/png_writer.h"

namespace ecpsim::render::testing {

inline std::string GoldenPath(const std::string& name) {
  return std::string(ECPSIM_SOURCE_DIR) + "/tests/golden/" + name + ".png";
}

inline std::string GoldenOutputDir() {
  const std::string dir = std::string(ECPSIM_BINARY_DIR) + "/tests/render/golden_output";
  std::filesystem::create_directories(dir);
  return dir;
}

inline bool Blessing() {
  const char* bless = std::getenv("ECPSIM_BLESS");
  return bless != nullptr && std::string(bless) == "1";
}

inline ::testing::AssertionResult MatchesGolden(const Image& actual, const std::string& name,
                                                const CompareTolerance& tolerance) {
  const std::string golden = GoldenPath(name);
  if (Blessing()) {
    WritePng(golden, actual, 9);
    return ::testing::AssertionSuccess() << "blessed " << golden;
  }
  const std::string actual_path = fmt::format("{}/{}.actual.png", GoldenOutputDir(), name);
  if (!std::filesystem::exists(golden)) {
    WritePng(actual_path, actual);
    return ::testing::AssertionFailure()
           << "no golden " << golden << "; actual frame written to " << actual_path
           << "; bless with scripts/bless_goldens.sh after checking it";
  }
  const ImageComparison comparison = CompareImages(ReadPng(golden), actual, tolerance);
  std::string diff_path = fmt::format("{}/{}.diff.png", GoldenOutputDir(), name);
  if (comparison.match) {
    // output of an earlier failure would mislead
    std::filesystem::remove(actual_path);
    std::filesystem::remove(diff_path);
    return ::testing::AssertionSuccess() << comparison.Summary(tolerance);
  }
  WritePng(actual_path, actual);
  if (comparison.diff.pixels.empty()) {
    diff_path = "(none: sizes differ)";
  } else {
    WritePng(diff_path, comparison.diff);
  }
  return ::testing::AssertionFailure()
         << name << ": " << comparison.Summary(tolerance) << "\n  golden: " << golden
         << "\n  actual: " << actual_path << "\n  diff:   " << diff_path
         << "\n  if the change is intended: scripts/bless_goldens.sh";
}

}  // namespace ecpsim::render::testing
