#include "engine/scene_limits.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ecpsim::engine {
namespace {

// duration / h within this relative slack of an integer counts as that integer, so 0.5 / 0.01
// (49.999999999999993 or 50.000000000000007 in floating point) gives 50 steps, not 51
constexpr double kStepCountSlack = 1e-9;

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
  return std::max(1L, static_cast<long>(std::ceil(ratio * (1 - kStepCountSlack))));
}

std::string StepCountProblem(double duration, double h) {
  const double ratio = duration / h;
  if (ratio * (1 - kStepCountSlack) <= static_cast<double>(kMaxSteps)) return "";
  return fmt::format(
      "at most {} steps per run, here duration / h = {:.3g} / {:.3g} = {:.3g} steps (beyond that "
      "the round-off of t += h exceeds 1% of a step); use a larger h or split the run",
      kMaxSteps, duration, h, ratio);
}

}  // namespace ecpsim::engine
