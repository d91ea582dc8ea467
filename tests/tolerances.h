#pragma once
// Tolerances that mean the same in every test folder, each with the reason for its value; a
// tolerance particular to one test lives in that test's file.

namespace ecpsim {

// a few ulps (ε = 2.2e-16) of a quantity of size ≲ 1 that takes a few operations
inline constexpr double kUnitRoundOff = 1e-15;

}  // namespace ecpsim
