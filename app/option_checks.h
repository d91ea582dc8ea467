#pragma once
// CLI11 checks of numeric options: finite and in range (CLI11's own PositiveNumber and Range let
// NaN through), with the ranges of engine/scene_limits.h. A value that fails throws InputError
// "--dt = nan: expected ...", so it is reported like any bad input (one line, exit code 1).

#include <CLI/CLI.hpp>
#include <string>

#include "engine/scene_limits.h"

namespace ecpsim::app {

/// `option` (its name for messages, "--dt"): a finite number > 0 within `range`.
CLI::Validator FinitePositive(const std::string& option, const engine::PositiveRange& range);

/// `option`: a finite number within ±engine::kMaxMagnitude (angles, velocities, heights).
CLI::Validator FiniteNumber(const std::string& option);

/// `option`: an integer in [min, max].
CLI::Validator IntegerInRange(const std::string& option, int min, int max);

/// `option` (--units): one of engine::KnownUnits().
CLI::Validator KnownUnit(const std::string& option);

}  // namespace ecpsim::app
