#pragma once
// Merging coincident vertices so that a triangle soup becomes an indexed, connected mesh.

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// Merges vertices closer than `tolerance` (metres) and drops triangles that become degenerate
/// (two equal indices). Formats like STL store every triangle's corners separately; welding is
/// what makes closedness and orientation checkable.
TriangleMesh WeldVertices(const TriangleMesh& mesh, double tolerance);

/// The default weld tolerance for a mesh: a fixed fraction of its bounding-box diagonal.
double DefaultWeldTolerance(const TriangleMesh& mesh);

}  // namespace ecpsim::geometry
