#include "engine/scene_limits.h"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace ecpsim::engine {
namespace {

// duration / h within this many steps of an integer counts as that integer, so 0.5 / 0.01
// (49.999999999999993 or 50.000000000000007 in floating point) gives 50 steps, not 51 ...
constexpr double kStepCountSlack = 1e-9;
// ... plus the quotient's own round-off, a few ulps of the count (1e10 steps: 1e-5 of a step);
// a slack proportional to the count (1e-9 · duration/h) would cut 10 steps off 1e10
constexpr double kStepCountRoundOffUlps = 8;

constexpr const char* kNameCharacters =
    "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-";

}  // namespace

bool IsValidName(const std::string& name) {
  return !name.empty() && name.find_first_not_of(kNameCharacters) == std::string::npos;
}

std::string OutOfRange(double value, const PositiveRange& range) {
  if (value >= range.min && value <= range.max) return "";
  return fmt::format("a {} in [{:g}, {:g}]{}{}", range.noun, range.min, range.max,
                     *range.unit ? " " : "", range.unit);
}

std::string OutOfMagnitude(double value) {
  if (std::abs(value) <= kMaxMagnitude) return "";
  return fmt::format("a finite number within ±{:g}", kMaxMagnitude);
}

long PlannedSteps(double duration, double h) {
  const double ratio = duration / h;
  const double nearest = std::round(ratio);
  const double slack = kStepCountSlack + kStepCountRoundOffUlps * DBL_EPSILON * ratio;
  const double steps = std::abs(ratio - nearest) <= slack ? nearest : std::ceil(ratio);
  return std::max(1L, static_cast<long>(steps));
}

std::string StepCountProblem(double duration, double h) {
  const double ratio = duration / h;
  if (ratio <= static_cast<double>(kMaxSteps)) return "";
  return fmt::format(
      "at most {} steps per run, here duration / h = {:.3g} / {:.3g} = {:.3g} steps (beyond that "
      "consecutive step times k·h are no longer distinct doubles); use a larger h or a shorter "
      "duration",
      kMaxSteps, duration, h, ratio);
}

}  // namespace ecpsim::engine
