#include "geometry/convex_decomposition.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "geometry/mesh_bounds.h"
#include "geometry/part_seams.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// whether face `f` of `a` lies within face `g` of `b` (on g's plane, facing it, every corner of f
// inside g's polygon), to `tolerance` m
bool FaceWithin(const ConvexHull& a, int f, const ConvexHull& b, int g, double tolerance,
                double size) {
  const Vector3d& n = a.normals[f];
  if ((n + b.normals[g]).norm() * size > tolerance) return false;
  if (std::abs(a.offsets[f] + b.offsets[g]) > tolerance) return false;
  // inside g: behind each of g's edges' planes, which are those of b's faces around g; it is
  // enough that each corner of f satisfies every constraint of b
  for (int i : a.faces[f]) {
    for (size_t c = 0; c < b.normals.size(); ++c)
      if (b.normals[c].dot(a.vertices[i]) - b.offsets[c] > tolerance) return false;
  }
  return true;
}

// whether every point of face f of `a` pushed `depth` along its normal lies inside `b`
bool ReachesBehind(const ConvexHull& a, int f, const ConvexHull& b, double depth,
                   double tolerance) {
  for (int i : a.faces[f]) {
    const Vector3d x = a.vertices[i] + depth * a.normals[f];
    for (size_t c = 0; c < b.normals.size(); ++c)
      if (b.normals[c].dot(x) - b.offsets[c] > tolerance) return false;
  }
  return true;
}

std::vector<Vector3d> Joined(const ConvexHull& a, const ConvexHull& b) {
  std::vector<Vector3d> points = a.vertices;
  points.insert(points.end(), b.vertices.begin(), b.vertices.end());
  return points;
}

}  // namespace

double HullVolume(const ConvexHull& hull) {
  // the divergence theorem over the fanned faces, about the first vertex (exact for a convex
  // polyhedron; the origin's choice only rounds)
  if (hull.vertices.empty()) return 0;
  const Vector3d& o = hull.vertices.front();
  double six_volume = 0;
  for (const std::vector<int>& face : hull.faces) {
    for (size_t k = 1; k + 1 < face.size(); ++k) {
      six_volume += (hull.vertices[face[0]] - o)
                        .dot((hull.vertices[face[k]] - o).cross(hull.vertices[face[k + 1]] - o));
    }
  }
  return six_volume / 6;
}

std::vector<ConvexHull> DecomposeSolid(const TriangleMesh& mesh, const std::string& source,
                                       std::size_t max_parts) {
  const double size = ComputeMeshBounds(mesh.vertices).diagonal;
  const double tolerance = kCoplanarTolerance * size;
  std::vector<ConvexHull> parts;
  for (const std::vector<Vector3d>& piece : ExactConvexPieces(mesh, source))
    parts.push_back(ComputeConvexHull(piece, source));
  // merge two pieces meeting face to face where their union is convex
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < parts.size() && !merged; ++i) {
      for (size_t j = i + 1; j < parts.size() && !merged; ++j) {
        if (!FindSeam(parts[i], parts[j], tolerance)) continue;
        ConvexHull joined = ComputeConvexHull(Joined(parts[i], parts[j]), source);
        const double sum = HullVolume(parts[i]) + HullVolume(parts[j]);
        if (HullVolume(joined) > sum + tolerance * size * size) continue;
        parts[i] = std::move(joined);
        parts.erase(parts.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
    }
  }
  if (parts.size() > max_parts) {
    throw InputError(fmt::format(
        "convex decomposition of {}: {} convex parts, more than {}; list the body's `parts` "
        "yourself (a coarser, approximate decomposition), or keep its hull "
        "(decomposition: none)",
        source, parts.size(), max_parts));
  }
  // move each seam inside the part that covers it (all against the parts as they were)
  const double depth = kSeamOverlapRel * size;
  std::vector<std::vector<Vector3d>> grown(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    for (size_t f = 0; f < parts[i].faces.size(); ++f) {
      for (size_t j = 0; j < parts.size(); ++j) {
        if (j == i || !ReachesBehind(parts[i], static_cast<int>(f), parts[j], depth, tolerance))
          continue;
        bool covered = false;
        for (size_t g = 0; g < parts[j].faces.size() && !covered; ++g) {
          covered = FaceWithin(parts[i], static_cast<int>(f), parts[j], static_cast<int>(g),
                               tolerance, size);
        }
        if (!covered) continue;
        for (int k : parts[i].faces[f])
          grown[i].push_back(parts[i].vertices[k] + depth * parts[i].normals[f]);
        break;
      }
    }
  }
  for (size_t i = 0; i < parts.size(); ++i) {
    if (grown[i].empty()) continue;
    grown[i].insert(grown[i].end(), parts[i].vertices.begin(), parts[i].vertices.end());
    parts[i] = ComputeConvexHull(grown[i], source);
  }
  return parts;
}

}  // namespace ecpsim::geometry
