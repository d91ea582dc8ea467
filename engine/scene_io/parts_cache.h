#pragma once
// A mesh's convex decomposition kept beside its file, so that it is computed once per mesh
// (`decomposition: auto`, docs/scene_format.md "Decomposition").

#include <functional>
#include <string>
#include <vector>

#include "geometry/convex_hull.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::engine {

/// The parts of `mesh` (body frame) within `tolerance` (× its diagonal), read from
/// `<mesh_file>.parts-<fingerprint>.txt` where that file holds them, else from `decompose()`,
/// then written there (atomically). The fingerprint is FNV-1a over the mesh's coordinates and
/// triangles, the tolerance and the decomposition's version, so a changed mesh, scale, frame or
/// tolerance never reads another's parts. The file lists each part's vertices in shortest
/// round-trip form: the hulls rebuilt from them are the decomposition's, bit for bit. A cache
/// that cannot be read as one is ignored and rewritten; one that cannot be written (a read-only
/// folder) adds a line to `warnings` and the parts are used as computed.
std::vector<geometry::ConvexHull> CachedDecomposition(
    const std::string& mesh_file, const geometry::TriangleMesh& mesh, double tolerance,
    const std::function<std::vector<geometry::ConvexHull>()>& decompose,
    std::vector<std::string>& warnings);

/// Where CachedDecomposition keeps the parts of `mesh` read from `mesh_file` within `tolerance`.
std::string DecompositionCachePath(const std::string& mesh_file, const geometry::TriangleMesh& mesh,
                                   double tolerance);

}  // namespace ecpsim::engine
