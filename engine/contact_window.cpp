#include "engine/contact_window.h"

#include <numeric>

#include <Eigen/Geometry>

namespace ecpsim::engine {

std::vector<int> SelectWindow(const geometry::ConvexShape& hull,
                              const Eigen::Vector3d& direction_B, int rings, bool use_window) {
  const auto* polyhedron = dynamic_cast<const geometry::PolyhedralShape*>(&hull);
  if (polyhedron == nullptr || !use_window || rings < 0) {
    std::vector<int> all(hull.NumConstraints());
    std::iota(all.begin(), all.end(), 0);
    return all;
  }
  return polyhedron->ConstraintsNearSupport(direction_B, rings);
}

bool WindowSolutionIsExact(const geometry::ConvexShape& hull, const std::vector<int>& window,
                           int active, const Eigen::Vector3d& y_B, double tolerance) {
  const auto* polyhedron = dynamic_cast<const geometry::PolyhedralShape*>(&hull);
  if (polyhedron == nullptr || static_cast<int>(window.size()) == hull.NumConstraints())
    return true;
  const geometry::ConvexHull& h = polyhedron->hull();
  const std::vector<int>& polygon = h.faces[active];
  const Eigen::Vector3d& normal = h.normals[active];
  // inside a counter-clockwise (seen from outside) polygon: left of every edge
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector3d& a = h.vertices[polygon[k]];
    const Eigen::Vector3d& b = h.vertices[polygon[(k + 1) % polygon.size()]];
    const Eigen::Vector3d edge = b - a;
    const double signed_distance = normal.dot(edge.cross(y_B - a)) / edge.norm();
    if (signed_distance < -tolerance) return false;
  }
  return true;
}

}  // namespace ecpsim::engine
