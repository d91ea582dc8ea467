#include "geometry/support_patch.h"

#include <cmath>
#include <vector>

#include "geometry/convex_hull.h"

namespace ecpsim::geometry {

using Eigen::Vector2d;
using Eigen::Vector3d;

ContactPatch SupportPatch(const ConvexShape& shape, const Eigen::Isometry3d& X_WB,
                          const Plane& plane, double tolerance) {
  const Vector3d& n = plane.normal;
  const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  const auto support = [&](const Vector3d& world_direction) {
    return Vector3d(X_WB * shape.Support(X_WB.linear().transpose() * world_direction));
  };
  const Vector3d base = support(-n);
  const Vector3d origin = base - (n.dot(base) - plane.offset) * n;
  std::vector<Vector2d> points{{u.dot(base - origin), v.dot(base - origin)}};
  for (int k = 0; k < kSupportProbes; ++k) {
    const double angle = 2 * M_PI * k / kSupportProbes;
    const Vector3d tilt = std::cos(angle) * u + std::sin(angle) * v;
    const Vector3d x = support(-n + kSupportProbeTilt * tilt);
    if (std::abs(n.dot(x) - plane.offset) <= tolerance)
      points.emplace_back(u.dot(x - origin), v.dot(x - origin));
  }
  const std::vector<Vector2d> hull = ComputeConvexHull2D(points);
  const auto world = [&](const Vector2d& p) { return Vector3d(origin + p.x() * u + p.y() * v); };
  ContactPatch patch;
  if (hull.size() >= 3) {
    std::vector<Vector3d> polygon;
    for (const Vector2d& p : hull) polygon.push_back(world(p));
    patch.polygons.push_back(polygon);
    patch.hull = polygon;
    for (std::size_t k = 0; k < hull.size(); ++k) {
      const Vector2d& a = hull[k];
      const Vector2d& b = hull[(k + 1) % hull.size()];
      patch.area += (a.x() * b.y() - a.y() * b.x()) / 2;
    }
    patch.feature_area = patch.area;
    patch.mode = ContactMode::kConvexPatch;
  } else if (hull.size() == 2 && (hull[1] - hull[0]).norm() > tolerance) {
    patch.segments.push_back({world(hull[0]), world(hull[1])});
    patch.hull = {world(hull[0]), world(hull[1])};
    patch.mode = ContactMode::kLine;
  } else {
    const Vector3d point = world(hull.empty() ? points[0] : hull[0]);
    patch.points.push_back(point);
    patch.hull = {point};
    patch.mode = ContactMode::kPoint;
  }
  return patch;
}

}  // namespace ecpsim::geometry
