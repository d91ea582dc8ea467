#pragma once
// Is a triangle mesh the boundary of a solid? Closedness and orientation checks.

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

struct MeshTopology {
  bool closed = false;                 // every edge is shared by exactly two triangles
  bool consistently_oriented = false;  // every shared edge is traversed in opposite directions
  int boundary_edges = 0;              // edges used by one triangle
  int non_manifold_edges = 0;          // edges used by three or more triangles
};

/// Edge-based topology of a welded mesh (run WeldVertices first for triangle soups).
MeshTopology AnalyzeTopology(const TriangleMesh& mesh);

}  // namespace ecpsim::geometry
