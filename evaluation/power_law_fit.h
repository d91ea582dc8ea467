#pragma once
// A power law y = c · x^k fitted to measurements: the exponent k of a cost against a size (k = 1:
// the cost grows in proportion to the size; 2: with its square).

#include <optional>
#include <vector>

namespace ecpsim::evaluation {

struct PowerLaw {
  double exponent = 0;     // k, the slope of log y against log x
  double coefficient = 0;  // c, y at x = 1
  int points = 0;          // the points fitted
};

/// The least-squares line through (log x, log y) of the points with x > 0 and y > 0 (both
/// finite); nullopt when fewer than two of them have distinct x. Precondition (ECPSIM_DEMAND):
/// x.size() == y.size().
std::optional<PowerLaw> FitPowerLaw(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace ecpsim::evaluation
