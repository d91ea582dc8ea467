#pragma once
// The byte stream from the mesh reader process (ecpsim-mesh-reader) back to LoadMesh: a header,
// then either an error message or the vertices and triangles. Both ends are built from the same
// sources for the same machine, so the layout is the native one (no byte swapping).

#include <cstdint>
#include <type_traits>

namespace ecpsim::geometry::mesh_stream {

/// First bytes of every stream; a different program behind the reader path fails here.
inline constexpr char kMagic[8] = {'E', 'C', 'P', 'M', 'E', 'S', 'H', '1'};

enum class Kind : std::uint32_t {
  kMesh = 0,         // followed by the vertices, then the triangles
  kError = 1,        // followed by message_bytes of text: why assimp could not read the file
  kOutOfMemory = 2,  // the reader hit its memory limit (nothing follows)
};

struct Header {
  char magic[8] = {};
  Kind kind = Kind::kError;
  std::uint32_t reserved = 0;
  std::uint64_t num_vertices = 0;   // kMesh: num_vertices × 3 doubles (x, y, z), file units
  std::uint64_t num_triangles = 0;  // kMesh: num_triangles × 3 std::int32_t vertex indices
  std::uint64_t num_meshes = 0;     // meshes in the file, for messages
  std::uint64_t other_faces = 0;    // point and line primitives left out, for messages
  std::uint64_t message_bytes = 0;  // kError: length of the message
};
static_assert(std::is_trivially_copyable_v<Header>);

/// Longest error message the reader sends (assimp's messages are one line).
inline constexpr std::uint64_t kMaxMessageBytes = 4096;

/// Exit codes of the reader: 0 the stream is complete, 1 an error record was sent, 2 bad usage.
inline constexpr int kExitOk = 0;
inline constexpr int kExitReported = 1;
inline constexpr int kExitUsage = 2;

}  // namespace ecpsim::geometry::mesh_stream
