#pragma once
// A convex shape moved by a rigid motion: the parts of a body, each given in the body's frame by
// its own position and orientation.

#include <memory>

#include <Eigen/Core>

#include "geometry/convex_shape.h"

namespace ecpsim::geometry {

/// `shape` moved by y ↦ R y + p (R a rotation). A polyhedron stays a PolyhedralShape, its hull
/// moved (vertices R v + p, normals R n, offsets d + R n · p; faces and adjacency as they were);
/// a smooth shape is wrapped: each constraint evaluated at Rᵀ (y − p), its gradient turned by R,
/// its Hessian by R · Rᵀ, its support point and tessellation moved. The identity motion returns
/// `shape` itself.
std::shared_ptr<const ConvexShape> Posed(std::shared_ptr<const ConvexShape> shape,
                                         const Eigen::Matrix3d& R, const Eigen::Vector3d& p);

}  // namespace ecpsim::geometry
