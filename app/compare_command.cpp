// `ecpsim compare EXPECTED.png ACTUAL.png`: image regression check with a per-pixel threshold and a
// bound on the fraction of differing pixels; exit 0 same, 1 different, 2 bad input.

#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "app/commands.h"
#include "common/errors.h"
#include "render/image_compare.h"
#include "render/png_writer.h"

namespace ecpsim::app {
namespace {

// exit codes of this command (diff(1) and cmp(1) use the same)
constexpr int kDifferent = 1;
constexpr int kBadInput = 2;

struct CompareOptions {
  std::string expected;
  std::string actual;
  std::string diff;
  render::CompareTolerance tolerance;
};

// returns 0 when the images match, kDifferent otherwise; throws InputError for bad input
int Compare(const CompareOptions& options) {
  const render::Image expected = render::ReadPng(options.expected);
  const render::Image actual = render::ReadPng(options.actual);
  const render::ImageComparison comparison =
      render::CompareImages(expected, actual, options.tolerance);
  if (!options.diff.empty() && !comparison.diff.pixels.empty()) {
    render::WritePng(options.diff, comparison.diff);
  }
  const std::string summary =
      comparison.same_size
          ? comparison.Summary(options.tolerance)
          : fmt::format("sizes differ: {} is {}x{}, {} is {}x{}", options.expected, expected.width,
                        expected.height, options.actual, actual.width, actual.height);
  std::printf("%s: %s\n", comparison.match ? "same" : "different", summary.c_str());
  if (!options.diff.empty() && !comparison.diff.pixels.empty()) {
    std::printf("diff image: %s\n", options.diff.c_str());
  }
  return comparison.match ? 0 : kDifferent;
}

}  // namespace

void AddCompareCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "compare",
      "Compare two PNG images (e.g. an `ecpsim render` frame with a blessed one). Exit 0: same "
      "within the tolerances; 1: different; 2: bad input (unreadable file, bad tolerance).");
  auto options = std::make_shared<CompareOptions>();
  command->add_option("EXPECTED", options->expected, "the reference PNG")->required();
  command->add_option("ACTUAL", options->actual, "the PNG to check")->required();
  command->add_option("--diff", options->diff,
                      "write a diff image here: differing pixels red, within-threshold orange");
  command
      ->add_option("--threshold", options->tolerance.channel_threshold,
                   "a pixel differs when a channel differs by more than N levels (0-255)")
      ->capture_default_str();
  command
      ->add_option("--max-fraction", options->tolerance.max_fraction,
                   "the images are the same when at most this fraction of pixels differ (0-1)")
      ->capture_default_str();
  command->callback([options] {
    int status = 0;
    try {
      status = Compare(*options);
    } catch (const InputError& e) {
      std::fprintf(stderr, "ecpsim: error: %s\n", e.what());
      throw CLI::RuntimeError(kBadInput);
    }
    if (status != 0) throw CLI::RuntimeError(status);
  });
}

}  // namespace ecpsim::app
