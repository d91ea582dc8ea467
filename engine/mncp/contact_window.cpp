#include "engine/mncp/contact_window.h"

#include <algorithm>
#include <numeric>

#include <Eigen/Geometry>

#include "common/errors.h"

namespace ecpsim::engine {

std::vector<int> SelectWindow(const geometry::ConvexShape& hull, const Eigen::Vector3d& direction_B,
                              int rings, bool use_window) {
  const auto* polyhedron = hull.AsPolyhedron();
  if (polyhedron == nullptr || !use_window || rings < 0) {
    std::vector<int> all(hull.NumConstraints());
    std::iota(all.begin(), all.end(), 0);
    return all;
  }
  return polyhedron->ConstraintsNearSupport(direction_B, rings);
}

namespace {

// calls visit(f) for every face f incident to a vertex of face `face` (itself included, once per
// vertex it shares) whose half-space y_B violates by more than `tolerance`, until visit returns
// false; false if it stopped
template <typename Visit>
bool ForEachViolatedNeighbour(const geometry::ConvexHull& h, int face, const Eigen::Vector3d& y_B,
                              double tolerance, Visit visit) {
  for (int vertex : h.faces[face])
    for (int other : h.vertex_faces[vertex])
      if (h.normals[other].dot(y_B) - h.offsets[other] > tolerance && !visit(other)) return false;
  return true;
}

}  // namespace

std::vector<int> WindowViolations(const geometry::ConvexShape& hull, const std::vector<int>& window,
                                  int active, const Eigen::Vector3d& y_B, double tolerance) {
  const auto* polyhedron = hull.AsPolyhedron();
  if (polyhedron == nullptr || static_cast<int>(window.size()) == hull.NumConstraints()) return {};
  std::vector<int> violated;
  ForEachViolatedNeighbour(polyhedron->hull(), active, y_B, tolerance, [&](int face) {
    // windows are sorted (SelectWindow, GrowWindow)
    if (!std::binary_search(window.begin(), window.end(), face)) violated.push_back(face);
    return true;
  });
  std::sort(violated.begin(), violated.end());
  violated.erase(std::unique(violated.begin(), violated.end()), violated.end());
  return violated;
}

bool OnFaceFacet(const geometry::PolyhedralShape& hull, int face, const Eigen::Vector3d& y_B,
                 double tolerance) {
  return ForEachViolatedNeighbour(hull.hull(), face, y_B, tolerance,
                                  [face](int other) { return other == face; });
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
