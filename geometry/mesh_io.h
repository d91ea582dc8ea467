#pragma once
// Reading and writing triangle meshes with assimp (the only place assimp is used).

#include <string>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// Loads every mesh of `path` (any format assimp reads: OBJ, STL ascii/binary, PLY, OFF, glTF/GLB,
/// DAE, 3DS, ...), applies node transforms, multiplies coordinates by `scale` (e.g. 0.001 for mm),
/// merges everything into one triangle mesh, and welds duplicate vertices (see WeldVertices).
/// @throws InputError naming `path` if the file is missing, unreadable, has no triangles, has
///         non-finite coordinates, or `scale` is not finite and > 0.
TriangleMesh LoadMesh(const std::string& path, double scale = 1.0);

/// Writes `mesh` to `path` in the format given by its extension (.obj, .stl, .ply), atomically
/// (temporary file + rename).
/// @throws InputError if the extension is unknown or the file cannot be written.
void SaveMesh(const TriangleMesh& mesh, const std::string& path);

}  // namespace ecpsim::geometry
