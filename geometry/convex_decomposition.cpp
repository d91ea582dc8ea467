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

// the part of convex polygon `subject` inside convex polygon `clip`, both counter-clockwise
// (Sutherland–Hodgman)
std::vector<Vector2d> Clip(std::vector<Vector2d> subject, const std::vector<Vector2d>& clip) {
  for (size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const Vector2d& a = clip[e];
    const Vector2d& b = clip[(e + 1) % clip.size()];
    const auto inside = [&](const Vector2d& p) {
      return (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
    };
    std::vector<Vector2d> kept;
    for (size_t k = 0; k < subject.size(); ++k) {
      const Vector2d& p = subject[k];
      const Vector2d& q = subject[(k + 1) % subject.size()];
      const double sp = inside(p), sq = inside(q);
      if (sp >= 0) kept.push_back(p);
      if ((sp >= 0) != (sq >= 0)) kept.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    subject = std::move(kept);
  }
  return subject;
}

// whether face f of parts[i] is a seam covered by the faces of other parts that lie on it,
// facing it, each of those parts reaching `depth` behind its share of f: the prism f × [0,
// depth] along f's normal is then inside those parts
bool SeamCovered(const std::vector<ConvexHull>& parts, size_t i, int f, double depth,
                 double tolerance, double size) {
  const ConvexHull& a = parts[i];
  const Vector3d& n = a.normals[f];
  const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  const std::vector<Vector2d> face = FaceInPlane(a, f, u, v);
  double covered = 0;
  for (size_t j = 0; j < parts.size(); ++j) {
    if (j == i) continue;
    const ConvexHull& b = parts[j];
    for (size_t g = 0; g < b.faces.size(); ++g) {
      if (!FacesMeet(a, f, b, static_cast<int>(g), tolerance, size)) continue;
      const std::vector<Vector2d> share = Clip(face, FaceInPlane(b, static_cast<int>(g), u, v));
      const double area = std::abs(SignedArea(share));
      if (area <= tolerance * size) continue;
      for (const Vector2d& corner : share) {
        const Vector3d x = (a.offsets[f] + depth) * n + corner.x() * u + corner.y() * v;
        for (size_t c = 0; c < b.normals.size(); ++c)
          if (b.normals[c].dot(x) - b.offsets[c] > tolerance) return false;
      }
      covered += area;
    }
  }
  return covered > 0 && covered >= SignedArea(face) - tolerance * size;
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
      if (!SeamCovered(parts, i, static_cast<int>(f), depth, tolerance, size)) continue;
      for (int k : parts[i].faces[f])
        grown[i].push_back(parts[i].vertices[k] + depth * parts[i].normals[f]);
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
