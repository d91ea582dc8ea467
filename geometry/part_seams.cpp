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

bool FacesMeet(const ConvexHull& a, int f, const ConvexHull& b, int g, double tolerance,
               double size) {
  return (a.normals[f] + b.normals[g]).norm() * size <= tolerance &&
         std::abs(a.offsets[f] + b.offsets[g]) <= tolerance;
}

std::vector<Vector2d> FaceInPlane(const ConvexHull& hull, int face, const Vector3d& u,
                                  const Vector3d& v) {
  std::vector<Vector2d> polygon;
  for (int i : hull.faces[face])
    polygon.emplace_back(u.dot(hull.vertices[i]), v.dot(hull.vertices[i]));
  if (SignedArea(polygon) < 0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

double SignedArea(const std::vector<Vector2d>& polygon) {
  double twice_area = 0;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Vector2d& p = polygon[k];
    const Vector2d& q = polygon[(k + 1) % polygon.size()];
    twice_area += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * twice_area;
}

std::optional<Seam> FindSeam(const ConvexHull& a, const ConvexHull& b, double tolerance) {
  const double size =
      std::max(ComputeMeshBounds(a.vertices).diagonal, ComputeMeshBounds(b.vertices).diagonal);
  if (!(size > 0)) return std::nullopt;
  for (size_t i = 0; i < a.faces.size(); ++i) {
    const Vector3d& n = a.normals[i];
    for (size_t j = 0; j < b.faces.size(); ++j) {
      if (!FacesMeet(a, static_cast<int>(i), b, static_cast<int>(j), tolerance, size)) continue;
      const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
      const std::vector<Vector2d> p = FaceInPlane(a, static_cast<int>(i), u, v);
      const std::vector<Vector2d> q = FaceInPlane(b, static_cast<int>(j), u, v);
      if (SmallestOverlap(p, q) <= tolerance) continue;
      Vector3d centre = Vector3d::Zero();
      for (int k : a.faces[i]) centre += a.vertices[k];
      return Seam{static_cast<int>(i), static_cast<int>(j), centre / a.faces[i].size()};
    }
  }
  return std::nullopt;
}

std::vector<Vector2d> ClipToSide(const std::vector<Vector2d>& polygon, const Vector2d& a,
                                 const Vector2d& b, bool left) {
  // > 0 on the kept side
  const auto side = [&](const Vector2d& p) {
    const double cross = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
    return left ? cross : -cross;
  };
  std::vector<Vector2d> kept;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Vector2d& p = polygon[k];
    const Vector2d& q = polygon[(k + 1) % polygon.size()];
    const double sp = side(p), sq = side(q);
    if (sp >= 0) kept.push_back(p);
    if ((sp >= 0) != (sq >= 0)) kept.push_back(p + (q - p) * (sp / (sp - sq)));
  }
  return kept;
}

}  // namespace ecpsim::geometry
