#include "evaluation/error_metrics.h"

#include <algorithm>
#include <cmath>

namespace ecpsim::evaluation {

TrajectoryErrors CompareTrajectories(const RunRecord& run, const RunRecord& reference,
                                     double length) {
  TrajectoryErrors e;
  const size_t n = std::min(run.samples.size(), reference.samples.size());
  int wrong = 0;
  for (size_t k = 0; k < n; ++k) {
    const engine::BodyState& a = run.samples[k];
    const engine::BodyState& b = reference.samples[k];
    const double dp = (a.p_WB - b.p_WB).norm();
    const double dtheta = a.Q_WB.angularDistance(b.Q_WB);
    e.position = std::max(e.position, dp);
    e.angle = std::max(e.angle, dtheta);
    e.state = std::max(e.state, dp + length * dtheta);
    e.velocity = std::max(e.velocity, (a.v_WB - b.v_WB).norm() + length * (a.w_WB - b.w_WB).norm());
    if (run.modes[k] != reference.modes[k]) ++wrong;
  }
  e.wrong_mode = n > 0 ? static_cast<double>(wrong) / static_cast<double>(n) : 0;
  if (run.stop_time >= 0 && reference.stop_time >= 0) {
    e.stop_time = std::abs(run.stop_time - reference.stop_time);
  }
  return e;
}

}  // namespace ecpsim::evaluation
