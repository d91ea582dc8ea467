#include "engine/contact_window.h"

#include <algorithm>
#include <numeric>

#include <Eigen/Geometry>

#include "common/errors.h"

namespace ecpsim::engine {

std::vector<int> SelectWindow(const geometry::ConvexShape& hull,
                              const Eigen::Vector3d& direction_B, int rings, bool use_window) {
  const auto* polyhedron = hull.AsPolyhedron();
  if (polyhedron == nullptr || !use_window || rings < 0) {
    std::vector<int> all(hull.NumConstraints());
    std::iota(all.begin(), all.end(), 0);
    return all;
  }
  return polyhedron->ConstraintsNearSupport(direction_B, rings);
}

std::vector<int> WindowViolations(const geometry::ConvexShape& hull,
                                  const std::vector<int>& window, int active,
                                  const Eigen::Vector3d& y_B, double tolerance) {
  const auto* polyhedron = hull.AsPolyhedron();
  if (polyhedron == nullptr || static_cast<int>(window.size()) == hull.NumConstraints()) return {};
  const geometry::ConvexHull& h = polyhedron->hull();
  std::vector<int> violated;
  for (int vertex : h.faces[active]) {
    for (int face : h.vertex_faces[vertex]) {
      // windows are sorted (SelectWindow, GrowWindow)
      if (std::binary_search(window.begin(), window.end(), face)) continue;
      if (h.normals[face].dot(y_B) - h.offsets[face] > tolerance) violated.push_back(face);
    }
  }
  std::sort(violated.begin(), violated.end());
  violated.erase(std::unique(violated.begin(), violated.end()), violated.end());
  return violated;
}

std::vector<int> GrowWindow(const geometry::ConvexShape& hull, const std::vector<int>& window,
                            const std::vector<int>& violated) {
  const auto* polyhedron = hull.AsPolyhedron();
  ECPSIM_DEMAND(polyhedron != nullptr);  // only polyhedra have windows smaller than the hull
  const geometry::ConvexHull& h = polyhedron->hull();
  std::vector<int> grown = window;
  for (int face : violated) {
    for (int vertex : h.faces[face]) {
      grown.insert(grown.end(), h.vertex_faces[vertex].begin(), h.vertex_faces[vertex].end());
    }
  }
  std::sort(grown.begin(), grown.end());
  grown.erase(std::unique(grown.begin(), grown.end()), grown.end());
  return grown;
}

}  // namespace ecpsim::engine
