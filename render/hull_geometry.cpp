// Display geometry of convex hulls: triangles for the translucent faces, edges with face normals.

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "render/frame_input.h"

namespace ecpsim::render {
namespace {

// Triangulates a convex polygon (counter-clockwise from outside) by cutting off every other
// corner as an ear, round after round, down to one central triangle. A fan from one corner
// makes n − 2 slivers each as long as the polygon is wide; these ears are short near the rim
// and the rounds' total edge length is about the perimeter times log2(n) instead of n times the
// width. llvmpipe pays per 4 × 4 pixel block that a triangle's edge crosses: on the 100k-triangle
// torus, whose hull has two flat 250-gons, this saved ~5% of the frame's CPU.
void AddEarTriangles(const std::vector<int>& polygon, geometry::TriangleMesh& mesh) {
  std::vector<int> ring = polygon, next;
  while (ring.size() > 3) {
    next.clear();
    size_t i = 0;
    for (; i + 2 < ring.size(); i += 2) {
      mesh.triangles.emplace_back(ring[i], ring[i + 1], ring[i + 2]);
      next.push_back(ring[i]);
    }
    // the corners past the last ear stay (one or two of them)
    for (; i < ring.size(); ++i) next.push_back(ring[i]);
    ring.swap(next);
  }
  if (ring.size() == 3) mesh.triangles.emplace_back(ring[0], ring[1], ring[2]);
}

}  // namespace

HullGeometry MakeHullGeometry(const geometry::ConvexHull& hull) {
  HullGeometry geometry;
  geometry.mesh.vertices = hull.vertices;
  for (const std::vector<int>& polygon : hull.faces) AddEarTriangles(polygon, geometry.mesh);

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
  if (const auto* polyhedron = shape.AsPolyhedron()) {
    return MakeHullGeometry(polyhedron->hull());
  }
  HullGeometry geometry;
  geometry.mesh = shape.Tessellate(segments);
  return geometry;
}

}  // namespace ecpsim::render
