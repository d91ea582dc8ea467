#include "geometry/hull_lids.h"

#include <cmath>

#include <Eigen/Geometry>

#include "geometry/mesh_bounds.h"
#include "geometry/part_seams.h"

namespace ecpsim::geometry {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Polygon = std::vector<Vector2d>;

// convex `polygon` less convex counter-clockwise `cut`, as disjoint convex pieces: for each edge
// of `cut` what lies right of it and left of the edges before it
void AppendDifference(Polygon polygon, const Polygon& cut, std::vector<Polygon>& pieces) {
  for (size_t e = 0; e < cut.size() && polygon.size() >= 3; ++e) {
    const Vector2d& a = cut[e];
    const Vector2d& b = cut[(e + 1) % cut.size()];
    Polygon outside = ClipToSide(polygon, a, b, false);
    if (outside.size() >= 3) pieces.push_back(std::move(outside));
    polygon = ClipToSide(polygon, a, b, true);
  }
}

}  // namespace

std::vector<int> UncoveredFaces(const ConvexHull& hull, const std::vector<const ConvexHull*>& parts,
                                double tolerance, double size) {
  std::vector<int> uncovered;
  for (size_t f = 0; f < hull.faces.size(); ++f) {
    const Vector3d& n = hull.normals[f];
    const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
    std::vector<Polygon> left = {FaceInPlane(hull, static_cast<int>(f), u, v)};
    for (const ConvexHull* part : parts) {
      for (size_t g = 0; g < part->faces.size() && !left.empty(); ++g) {
        // on the face's plane, facing its way
        if ((part->normals[g] - n).norm() * size > tolerance ||
            std::abs(part->offsets[g] - hull.offsets[f]) > tolerance) {
          continue;
        }
        const Polygon cut = FaceInPlane(*part, static_cast<int>(g), u, v);
        std::vector<Polygon> rest;
        for (Polygon& piece : left) AppendDifference(std::move(piece), cut, rest);
        left = std::move(rest);
      }
    }
    double area = 0;
    for (const Polygon& piece : left) area += std::abs(SignedArea(piece));
    if (area > tolerance * size) uncovered.push_back(static_cast<int>(f));
  }
  return uncovered;
}

ConvexHull LidSlab(const ConvexHull& hull, int face, double depth) {
  std::vector<Vector3d> points;
  for (int i : hull.faces[face]) {
    points.push_back(hull.vertices[i]);
    points.push_back(hull.vertices[i] - depth * hull.normals[face]);
  }
  return ComputeConvexHull(points, "a lid of a hull");
}

std::vector<std::shared_ptr<const ConvexShape>> LidSlabs(
    std::shared_ptr<const ConvexShape> hull,
    const std::vector<std::shared_ptr<const ConvexShape>>& parts) {
  const PolyhedralShape* polyhedron = hull->AsPolyhedron();
  if (polyhedron == nullptr) return {hull};
  const ConvexHull& faces = polyhedron->hull();
  const double size = ComputeMeshBounds(faces.vertices).diagonal;
  std::vector<const ConvexHull*> covering;
  for (const auto& part : parts) {
    if (const PolyhedralShape* part_polyhedron = part->AsPolyhedron())
      covering.push_back(&part_polyhedron->hull());
  }
  std::vector<std::shared_ptr<const ConvexShape>> lids;
  for (int face : UncoveredFaces(faces, covering, kCoplanarTolerance * size, size)) {
    lids.push_back(std::make_shared<PolyhedralShape>(LidSlab(faces, face, kLidDepthRel * size)));
  }
  return lids;
}

}  // namespace ecpsim::geometry
