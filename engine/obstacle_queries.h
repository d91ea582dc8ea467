#pragma once
// Queries of a convex obstacle G (or any ConvexShape in world coordinates) that every contact
// model shares: the face a point is in front of, its normal there, the projection onto it, and
// the tangent reference of a contact frame.

#include <utility>

#include <Eigen/Core>

#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// Index of the obstacle constraint with the largest value at `point` (world): the face of G a
/// body at `point` is in front of (for a half-space, 0).
int LargestConstraint(const geometry::ConvexShape& obstacle, const Eigen::Vector3d& point);

/// Unit outward normal of that constraint at `point`: the side of G a body at `point` faces.
Eigen::Vector3d ObstacleNormalToward(const geometry::ConvexShape& obstacle,
                                     const Eigen::Vector3d& point);

/// The closest point of G to `point` along the gradient of its largest constraint (exact for
/// linear constraints, a Newton step for smooth ones), and that constraint's index.
std::pair<Eigen::Vector3d, int> ProjectOntoObstacle(const geometry::ConvexShape& obstacle,
                                                    const Eigen::Vector3d& point);

/// The world axis least aligned with the normal `n` (need not be unit): a contact frame's tangent
/// t is it projected on the tangent plane, fixed for the step (MakeContactFrame).
Eigen::Vector3d TangentReference(const Eigen::Vector3d& n);

}  // namespace ecpsim::engine
