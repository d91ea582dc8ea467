#pragma once
// The hull model's warm start of a contact (ContactState::warm_start).

#include <vector>

#include <Eigen/Core>

#include "engine/models/solution_trend.h"

namespace ecpsim::engine {

/// The hull model's unknowns of one contact that ContactState's own fields do not hold: the gap s,
/// G's multipliers l_G (over `other_window`, G's constraints in the MNCP: empty for a fixed
/// obstacle, whose every constraint enters in order) and the hull multipliers l of F's window
/// (sorted face indices); and how the contact's solution has been changing (the predicted start).
struct HullWarmStart {
  double s = 0;
  Eigen::VectorXd l_g;
  std::vector<int> window;
  Eigen::VectorXd l;
  std::vector<int> other_window;
  SolutionTrend trend;
};

}  // namespace ecpsim::engine
