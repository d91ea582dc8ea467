#pragma once
// Merging coincident vertices so that a triangle soup becomes an indexed, connected mesh.

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// Merges vertices closer than `tolerance` (metres) and drops triangles that become degenerate
/// (two equal indices). Formats like STL store every triangle's corners separately; welding is
/// what makes closedness and orientation checkable.
/// @pre `tolerance` finite and ≥ 0, every vertex finite, triangle indices valid (bugs otherwise:
///      LoadMesh checks all three, with the mesh in the range of geometry/mesh_bounds.h).
TriangleMesh WeldVertices(const TriangleMesh& mesh, double tolerance);

/// The default weld tolerance for a mesh: 1e-7 of its bounding-box diagonal (0 for no vertices).
/// Finite for every finite mesh whose bounding box spans less than the double range.
double DefaultWeldTolerance(const TriangleMesh& mesh);

}  // namespace ecpsim::geometry
