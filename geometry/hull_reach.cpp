#include "geometry/hull_reach.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector3d;

// a cube of the octree
struct Cell {
  Vector3d centre;
  double half = 0;  // m, half its edge
};

// whether the cell lies beyond one of the hull's face planes (its least n · y there)
bool Outside(const ConvexHull& hull, const Cell& cell) {
  for (std::size_t f = 0; f < hull.normals.size(); ++f) {
    const Vector3d& n = hull.normals[f];
    if (n.dot(cell.centre) - cell.half * n.cwiseAbs().sum() > hull.offsets[f]) return true;
  }
  return false;
}

// a known part, and which of its faces lie on a face plane of the hull
struct Known {
  const ConvexHull* part = nullptr;
  std::vector<bool> on_hull;
};

// (normals within kCoplanarTolerance, offsets within `tolerance` m, as the hull merges faces)
Known OnHull(const ConvexHull& part, const ConvexHull& hull, double tolerance) {
  Known known{&part, std::vector<bool>(part.normals.size(), false)};
  for (std::size_t f = 0; f < part.normals.size(); ++f) {
    for (std::size_t g = 0; g < hull.normals.size() && !known.on_hull[f]; ++g) {
      known.on_hull[f] = (part.normals[f] - hull.normals[g]).norm() <= kCoplanarTolerance &&
                         std::abs(part.offsets[f] - hull.offsets[g]) <= tolerance;
    }
  }
  return known;
}

// whether the part of the cell in the hull lies in the known part: the cell is within each face
// plane of the part that is not one of the hull's (the hull holds the cell to those)
bool Inside(const Known& known, const Cell& cell) {
  const ConvexHull& part = *known.part;
  for (std::size_t f = 0; f < part.normals.size(); ++f) {
    const Vector3d& n = part.normals[f];
    if (!known.on_hull[f] && n.dot(cell.centre) + cell.half * n.cwiseAbs().sum() > part.offsets[f])
      return false;
  }
  return true;
}

bool Contains(const ConvexHull& hull, const Vector3d& y) {
  for (std::size_t f = 0; f < hull.normals.size(); ++f)
    if (hull.normals[f].dot(y) > hull.offsets[f]) return false;
  return true;
}

// whether every triangle of `mesh` that meets the hull's box [lower, upper] lies beyond or on
// one of the hull's face planes, within `tolerance` m: then the surface does not enter the hull
bool ClearOfSurface(const ConvexHull& hull, const TriangleMesh& mesh, const Vector3d& lower,
                    const Vector3d& upper, double tolerance) {
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Vector3d& a = mesh.vertices[t[0]];
    const Vector3d& b = mesh.vertices[t[1]];
    const Vector3d& c = mesh.vertices[t[2]];
    if ((a.cwiseMin(b).cwiseMin(c) - upper).maxCoeff() > tolerance ||
        (lower - a.cwiseMax(b).cwiseMax(c)).maxCoeff() > tolerance) {
      continue;
    }
    bool beyond = false;
    for (std::size_t f = 0; f < hull.normals.size() && !beyond; ++f) {
      const Vector3d& n = hull.normals[f];
      beyond = std::min({n.dot(a), n.dot(b), n.dot(c)}) >= hull.offsets[f] - tolerance;
    }
    if (!beyond) return false;
  }
  return true;
}

}  // namespace

bool ReachesWithin(const ConvexHull& hull, const std::vector<const ConvexHull*>& known,
                   const TriangleMesh& mesh, const SolidDistance& solid, double bound) {
  ECPSIM_DEMAND(bound > 0 && !hull.vertices.empty());
  Vector3d lower = hull.vertices.front(), upper = lower;
  for (const Vector3d& v : hull.vertices) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  const double tolerance = kCoplanarTolerance * (upper - lower).norm();
  if (ClearOfSurface(hull, mesh, lower, upper, tolerance)) return true;
  std::vector<Known> parts;
  for (const ConvexHull* part : known) parts.push_back(OnHull(*part, hull, tolerance));
  const double finest = kReachCellRel * bound;
  const double root3 = std::sqrt(3.0);
  // breadth first, so that a hull reaching far out is refused at a coarse cell
  std::deque<Cell> cells{{(lower + upper) / 2, (upper - lower).maxCoeff() / 2}};
  while (!cells.empty()) {
    const Cell cell = cells.front();
    cells.pop_front();
    if (Outside(hull, cell)) continue;
    if (std::any_of(parts.begin(), parts.end(),
                    [&](const Known& part) { return Inside(part, cell); })) {
      continue;
    }
    // the distance is 1-Lipschitz: each point of the cell is within `radius` of the centre's
    const double radius = root3 * cell.half;
    const double distance = solid.ToSurface(cell.centre);
    if (distance + radius <= bound) continue;
    // a cell in the solid; the centre, a point of the hull, out of reach; else halve the cell
    // (at the finest, undecided: refused)
    const bool inside = solid.Inside(cell.centre);
    if (inside && distance >= radius) continue;
    if (!inside && distance - radius > bound && Contains(hull, cell.centre)) return false;
    if (radius <= finest) return false;
    for (int k = 0; k < 8; ++k) {
      const Vector3d corner((k & 1) ? 1 : -1, (k & 2) ? 1 : -1, (k & 4) ? 1 : -1);
      cells.push_back({cell.centre + cell.half / 2 * corner, cell.half / 2});
    }
  }
  return true;
}

}  // namespace ecpsim::geometry
