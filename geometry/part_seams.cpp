#include "geometry/part_seams.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/mesh_bounds.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// the face's corners in the plane's coordinates (u, v): counter-clockwise seen along `normal`
std::vector<Vector2d> InPlane(const ConvexHull& hull, int face, const Vector3d& u,
                              const Vector3d& v) {
  std::vector<Vector2d> corners;
  for (int i : hull.faces[face])
    corners.emplace_back(u.dot(hull.vertices[i]), v.dot(hull.vertices[i]));
  return corners;
}

// the smallest overlap of two convex polygons' projections over the edge normals of both (< 0:
// an axis separates them)
double SmallestOverlap(const std::vector<Vector2d>& p, const std::vector<Vector2d>& q) {
  double smallest = INFINITY;
  for (const std::vector<Vector2d>* polygon : {&p, &q}) {
    const size_t n = polygon->size();
    for (size_t i = 0; i < n; ++i) {
      const Vector2d edge = (*polygon)[(i + 1) % n] - (*polygon)[i];
      const Vector2d axis = Vector2d(edge.y(), -edge.x()).normalized();
      const auto extent = [&](const std::vector<Vector2d>& points) {
        double lo = INFINITY, hi = -INFINITY;
        for (const Vector2d& x : points) {
          lo = std::min(lo, axis.dot(x));
          hi = std::max(hi, axis.dot(x));
        }
        return std::pair(lo, hi);
      };
      const auto [lo_p, hi_p] = extent(p);
      const auto [lo_q, hi_q] = extent(q);
      smallest = std::min(smallest, std::min(hi_p, hi_q) - std::max(lo_p, lo_q));
    }
  }
  return smallest;
}

}  // namespace

std::optional<Seam> FindSeam(const ConvexHull& a, const ConvexHull& b, double tolerance) {
  const double size =
      std::max(ComputeMeshBounds(a.vertices).diagonal, ComputeMeshBounds(b.vertices).diagonal);
  if (!(size > 0)) return std::nullopt;
  for (size_t i = 0; i < a.faces.size(); ++i) {
    const Vector3d& n = a.normals[i];
    for (size_t j = 0; j < b.faces.size(); ++j) {
      if ((n + b.normals[j]).norm() * size > tolerance) continue;
      if (std::abs(a.offsets[i] + b.offsets[j]) > tolerance) continue;
      const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
      const std::vector<Vector2d> p = InPlane(a, static_cast<int>(i), u, v);
      const std::vector<Vector2d> q = InPlane(b, static_cast<int>(j), u, v);
      if (SmallestOverlap(p, q) <= tolerance) continue;
      Vector3d centre = Vector3d::Zero();
      for (int k : a.faces[i]) centre += a.vertices[k];
      return Seam{static_cast<int>(i), static_cast<int>(j), centre / a.faces[i].size()};
    }
  }
  return std::nullopt;
}

}  // namespace ecpsim::geometry
