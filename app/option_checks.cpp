#include "app/option_checks.h"

#include <fmt/format.h>

#include <cmath>

#include "common/errors.h"
#include "engine/scene_io/mesh_scale.h"

namespace ecpsim::app {
namespace {

// a validator that throws InputError "OPTION = TEXT: expected ..." when `problem` returns text
template <typename Problem>
CLI::Validator Throwing(const std::string& option, const std::string& description,
                        Problem problem) {
  return CLI::Validator(
      [option, problem](std::string& text) -> std::string {
        const std::string expected = problem(text);
        if (!expected.empty()) {
          throw InputError(fmt::format("{} = {}: expected {}", option, text, expected));
        }
        return "";
      },
      description);
}

// the option's text as a finite double; false when it is no number or not finite
bool ParseFinite(const std::string& text, double& value) {
  return CLI::detail::lexical_cast(text, value) && std::isfinite(value);
}

}  // namespace

CLI::Validator FinitePositive(const std::string& option, const engine::PositiveRange& range) {
  return Throwing(option, fmt::format("{} in [{:g}, {:g}]", range.noun, range.min, range.max),
                  [range](const std::string& text) -> std::string {
                    double value = 0;
                    if (!ParseFinite(text, value) || !(value > 0)) {
                      return fmt::format("a finite {} > 0{}{}", range.noun, *range.unit ? " " : "",
                                         range.unit);
                    }
                    return engine::OutOfRange(value, range);
                  });
}

CLI::Validator FiniteNumber(const std::string& option) {
  return Throwing(option, "FINITE", [](const std::string& text) -> std::string {
    double value = 0;
    if (!ParseFinite(text, value) || !engine::OutOfMagnitude(value).empty()) {
      return fmt::format("a finite number within ±{:g}", engine::kMaxMagnitude);
    }
    return "";
  });
}

CLI::Validator IntegerInRange(const std::string& option, int min, int max) {
  return Throwing(option, fmt::format("INT in [{}, {}]", min, max),
                  [min, max](const std::string& text) -> std::string {
                    long long value = 0;
                    if (!CLI::detail::lexical_cast(text, value) || value < min || value > max) {
                      return fmt::format("an integer in [{}, {}]", min, max);
                    }
                    return "";
                  });
}

CLI::Validator KnownUnit(const std::string& option) {
  return Throwing(option, engine::KnownUnits(), [](const std::string& text) -> std::string {
    return engine::MetresPerUnit(text) ? "" : fmt::format("one of {}", engine::KnownUnits());
  });
}

}  // namespace ecpsim::app
