#pragma once
// Reading and writing triangle meshes: reading through the assimp reader process (geometry/
// mesh_reader_process.h), writing with assimp's exporter in-process.

#include <string>

#include "geometry/mesh_reader_process.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// Loads every mesh of `path` (any format assimp reads: OBJ, STL ascii/binary, PLY, OFF, glTF/GLB,
/// DAE, 3DS, FBX, ...), applies node transforms (re-winding the triangles of mirroring ones, so
/// they keep facing outward), multiplies coordinates by `scale` (e.g. 0.001 for mm), merges
/// everything into one triangle mesh, and welds duplicate vertices (see WeldVertices).
/// assimp runs in a separate process under memory and time limits (MeshReaderLimitsForFile:
/// ≥ 1 GiB and ≥ 5 s, more for large files), so a corrupt file that crashes assimp or makes it
/// allocate without end is an InputError, never a crash or a hang of the caller.
/// The scaled mesh must have a bounding-box diagonal in [kMinMeshSize, kMaxMeshSize] = [1e-20 m,
/// 1e20 m] and every |coordinate| ≤ 1e20 m (geometry/mesh_bounds.h): within that range welding,
/// topology, hulls and mass properties (∝ L⁵) stay finite and accurate.
/// @throws InputError naming `path` if the file is missing, unreadable, crashes or exceeds the
///         limits of the reader ("cannot read the mesh: ..."), has no triangles, has non-finite
///         coordinates, or if `scale` is not finite and > 0 or puts the mesh outside the range.
/// @throws std::runtime_error if the reader program ecpsim-mesh-reader cannot be started.
TriangleMesh LoadMesh(const std::string& path, double scale = 1.0);

/// As LoadMesh, with the reader's limits chosen by the caller instead of MeshReaderLimitsForFile
/// (e.g. a test running hundreds of corrupt files, some of which make assimp loop forever).
TriangleMesh LoadMesh(const std::string& path, double scale, const MeshReaderLimits& limits);

/// Writes `mesh` to `path` in the format given by its extension (.obj, .stl, .ply), atomically
/// (temporary file + rename).
/// @throws InputError if the extension is unknown or the file cannot be written.
void SaveMesh(const TriangleMesh& mesh, const std::string& path);

}  // namespace ecpsim::geometry
