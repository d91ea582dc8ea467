#pragma once
// The three error tiers of ecpsim: bugs (ECPSIM_DEMAND), bad input (InputError), numerics (engine's
// SolverFailure).

#include <stdexcept>
#include <string>

namespace ecpsim {

/// Bad input from a user: a mesh, a scene file, a command-line value. The message names the
/// source (file, line/key), the offending value and what was expected.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Aborts with file:line; used for broken invariants (bugs), never for user input.
[[noreturn]] void DemandFailed(const char* condition, const char* file, int line);

}  // namespace ecpsim

#define ECPSIM_DEMAND(condition) \
  ((condition) ? static_cast<void>(0) : ::ecpsim::DemandFailed(#condition, __FILE__, __LINE__))
