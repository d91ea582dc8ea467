#include "engine/obstacle_queries.h"

namespace ecpsim::engine {

int LargestConstraint(const geometry::ConvexShape& obstacle, const Eigen::Vector3d& point) {
  int best = 0;
  double best_value = obstacle.Value(0, point);
  for (int j = 1; j < obstacle.NumConstraints(); ++j) {
    const double value = obstacle.Value(j, point);
    if (value > best_value) {
      best_value = value;
      best = j;
    }
  }
  return best;
}

Eigen::Vector3d ObstacleNormalToward(const geometry::ConvexShape& obstacle,
                                     const Eigen::Vector3d& point) {
  return obstacle.Gradient(LargestConstraint(obstacle, point), point).normalized();
}

std::pair<Eigen::Vector3d, int> ProjectOntoObstacle(const geometry::ConvexShape& obstacle,
                                                    const Eigen::Vector3d& point) {
  const int best = LargestConstraint(obstacle, point);
  const Eigen::Vector3d grad = obstacle.Gradient(best, point);
  return {point - obstacle.Value(best, point) * grad / grad.squaredNorm(), best};
}

Eigen::Vector3d TangentReference(const Eigen::Vector3d& n) {
  int axis;
  n.cwiseAbs().minCoeff(&axis);
  return Eigen::Vector3d::Unit(axis);
}

}  // namespace ecpsim::engine
