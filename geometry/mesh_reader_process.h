#pragma once
// Reading a mesh file with assimp in a separate, limited process, so that a crash or a runaway
// allocation inside assimp on a corrupt file becomes an error message, never a crash of ecpsim.

#include <cstddef>
#include <cstdint>
#include <string>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// Limits of one reader process.
struct MeshReaderLimits {
  std::uint64_t memory_bytes = 0;  // address space of the reader, and the most LoadMesh accepts
                                   // for the mesh it sends back (vertices + triangles)
  double seconds = 0;              // wall-clock time until the reader is killed
};

/// The limits LoadMesh uses for a file of `file_bytes` bytes: a floor plus a multiple of the size
/// (see the constants in mesh_reader_process.cpp for the measurements behind them). A 1M-triangle
/// STL (50 MB) gets 1.8 GB and 10 s; a 300-byte file 1 GiB and 5 s.
MeshReaderLimits MeshReaderLimitsForFile(std::uint64_t file_bytes);

/// What the reader sends back: every mesh instance of the file in the file's root frame (node
/// transforms applied in double precision, triangles of mirroring transforms re-wound so they
/// keep facing outward), in file units, not yet welded; plus counts for messages.
struct ImportedMesh {
  TriangleMesh mesh;
  std::size_t num_meshes = 0;   // meshes in the file
  std::size_t other_faces = 0;  // point and line primitives left out
};

/// Reads `path` with assimp in the helper program ecpsim-mesh-reader (found as $ECPSIM_MESH_READER,
/// next to the running executable, or in the build tree, in that order), which streams the
/// triangles back through a pipe. Safe in a multi-threaded process (posix_spawn, close-on-exec
/// pipes); the child is always reaped, also when this throws.
/// @throws InputError "<path>: cannot read the mesh: ..." when assimp reports an error, crashes,
///         exceeds `limits`, or the scene it builds is malformed.
/// @throws std::runtime_error when the reader program cannot be started or speaks another format
///         (an installation problem, not bad input).
ImportedMesh ReadMeshInReaderProcess(const std::string& path, const MeshReaderLimits& limits);

}  // namespace ecpsim::geometry
