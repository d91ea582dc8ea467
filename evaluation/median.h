#pragma once
// The median of a few measurements (timings of one run repeated, ratios over a sweep).

#include <algorithm>
#include <vector>

#include "common/errors.h"

namespace ecpsim::evaluation {

/// The middle value of `values` (the mean of the two middle ones for an even count); not empty.
inline double Median(std::vector<double> values) {
  ECPSIM_DEMAND(!values.empty());
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace ecpsim::evaluation
