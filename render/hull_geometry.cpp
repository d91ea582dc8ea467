// Display geometry of convex hulls: triangles for the translucent faces, edges with face normals.

#include <algorithm>
#include <map>
#include <utility>

#include "render/frame_input.h"

namespace ecpsim::render {

HullGeometry MakeHullGeometry(const geometry::ConvexHull& hull) {
  HullGeometry geometry;
  geometry.mesh = geometry::TriangulateHull(hull);

  // each undirected edge of the polygon faces, with the faces on either side
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (size_t f = 0; f < hull.faces.size(); ++f) {
    const auto& face = hull.faces[f];
    for (size_t k = 0; k < face.size(); ++k) {
      const int a = face[k], b = face[(k + 1) % face.size()];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(f));
    }
  }
  for (const auto& [edge, faces] : edge_faces) {
    HullEdge e;
    e.a = hull.vertices[edge.first];
    e.b = hull.vertices[edge.second];
    e.n_left = hull.normals[faces.front()];
    e.n_right = hull.normals[faces.back()];
    geometry.edges.push_back(e);
  }
  return geometry;
}

HullGeometry MakeHullGeometry(const geometry::ConvexShape& shape, int segments) {
  if (const auto* polyhedron = dynamic_cast<const geometry::PolyhedralShape*>(&shape)) {
    return MakeHullGeometry(polyhedron->hull());
  }
  HullGeometry geometry;
  geometry.mesh = shape.Tessellate(segments);
  return geometry;
}

}  // namespace ecpsim::render
