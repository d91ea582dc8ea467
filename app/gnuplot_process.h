#pragma once
// Running the gnuplot program on a script file (an argument vector, no shell).

#include <string>

namespace ecpsim::app {

/// Runs `gnuplot SCRIPT` (found on PATH) in the current folder, with its stdout and stderr
/// written to `log_path`, and waits for it.
/// @throws InputError if gnuplot is not installed (naming the Debian package gnuplot-nox and
///         scripts/setup.sh), cannot be started, or exits with an error (quoting the end of its
///         log).
void RunGnuplot(const std::string& script_path, const std::string& log_path);

}  // namespace ecpsim::app
