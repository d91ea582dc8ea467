#pragma once
// Where a convex shape lies on a plane it touches, from its support points alone: the contact
// patch of a smooth primitive (a cylinder's side is a segment, its end a disc, a sphere a point),
// whose display mesh would put facets and vertices of its own tessellation there instead.

#include <Eigen/Geometry>

#include "geometry/contact_patch.h"
#include "geometry/convex_shape.h"

namespace ecpsim::geometry {

/// The support features of `shape` (body frame, posed by `X_WB`) on `plane` (n · x = offset,
/// the shape on the side n points away from): its support point along −n and its support points
/// along −n tilted by kSupportProbeTilt towards kSupportProbes directions of the plane, those
/// within `tolerance` (m) of the plane, as a polygon (their convex hull: for a disc, an inscribed
/// kSupportProbes-gon), a segment or a point.
ContactPatch SupportPatch(const ConvexShape& shape, const Eigen::Isometry3d& X_WB,
                          const Plane& plane, double tolerance);

/// The probes' tilt (rad): any angle picks a flat feature's extreme points, while a curved
/// surface's support leaves the plane by its radius times 1 − cos(tilt) ≈ 1.2e-3, far beyond the
/// patch tolerances (1e-6 of the body's size), so curvature never widens a line into a sliver
inline constexpr double kSupportProbeTilt = 0.05;
/// Directions probed about the normal: a disc becomes a regular 16-gon (area 2.5 % short).
inline constexpr int kSupportProbes = 16;

}  // namespace ecpsim::geometry
