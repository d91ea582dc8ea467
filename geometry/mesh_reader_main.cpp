// ecpsim-mesh-reader: reads one mesh file with assimp and streams its triangles to LoadMesh.
//
// Usage (by LoadMesh only): ecpsim-mesh-reader OUTPUT_FD MEMORY_BYTES CPU_SECONDS PARENT_PID PATH
//
// assimp runs here, in a process of its own under memory and CPU limits, so that a crash, an
// abort or a runaway allocation inside it on a corrupt file ends this process, not ecpsim (see
// geometry/mesh_reader_process.h). The stream format is geometry/mesh_stream.h.

#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <Eigen/Core>
#include <Eigen/LU>
#include <assimp/Importer.hpp>

#include "geometry/mesh_stream.h"

namespace ecpsim::geometry {
namespace {

namespace ms = mesh_stream;

// vertices and index triples per write: 4096 × 24 B = 96 KiB, a few pipe buffers
constexpr std::size_t kChunk = 4096;

// a corrupt file detected while walking the scene (not assimp's own error)
struct MalformedScene : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// writes all `size` bytes to `fd`, retrying after signals; false if the reading end is gone
bool WriteAll(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

ms::Header MakeHeader(ms::Kind kind) {
  ms::Header header;
  std::memcpy(header.magic, ms::kMagic, sizeof(header.magic));
  header.kind = kind;
  return header;
}

int SendError(int fd, std::string message) {
  if (message.size() > ms::kMaxMessageBytes) message.resize(ms::kMaxMessageBytes);
  ms::Header header = MakeHeader(ms::Kind::kError);
  header.message_bytes = message.size();
  WriteAll(fd, &header, sizeof(header));
  WriteAll(fd, message.data(), message.size());
  return ms::kExitReported;
}

int SendOutOfMemory(int fd) {
  const ms::Header header = MakeHeader(ms::Kind::kOutOfMemory);
  WriteAll(fd, &header, sizeof(header));
  return ms::kExitReported;
}

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4,  //
      m.b1, m.b2, m.b3, m.b4,   //
      m.c1, m.c2, m.c3, m.c4,   //
      m.d1, m.d2, m.d3, m.d4;
  return e;
}

// one mesh placed by one node: its vertices map by `transform` into the root frame
struct Instance {
  const aiMesh* mesh;
  Eigen::Matrix4d transform;
  bool mirrored;  // det < 0: the transform turns outward winding inward
};

// every mesh instance of the scene, with node transforms composed in double precision; checks
// every pointer and index the stream will touch, since a corrupt file can leave assimp's scene
// malformed (the RAW importer leaves null child nodes). assimp's own ValidateDataStructure
// step is not used: it also rejects good geometry beside irrelevant defects (a light without a
// node, an empty STL solid).
std::vector<Instance> CollectInstances(const aiScene& scene, std::uint64_t& num_vertices,
                                       std::uint64_t& num_triangles, std::uint64_t& other_faces) {
  std::vector<Instance> instances;
  num_vertices = num_triangles = other_faces = 0;
  if (scene.mRootNode == nullptr) return instances;
  std::unordered_set<const aiNode*> seen;
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> pending = {
      {scene.mRootNode, Eigen::Matrix4d::Identity()}};
  while (!pending.empty()) {
    const auto [node, parent] = pending.back();
    pending.pop_back();
    // each node has one parent: meeting a node twice means a cycle or shared child
    if (!seen.insert(node).second) {
      throw MalformedScene(
          fmt::format("node '{}' appears twice in the node tree", node->mName.C_Str()));
    }
    const Eigen::Matrix4d transform = parent * ToEigen(node->mTransformation);
    const bool mirrored = transform.topLeftCorner<3, 3>().determinant() < 0.0;
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const unsigned index = node->mMeshes[m];
      if (index >= scene.mNumMeshes || scene.mMeshes[index] == nullptr) {
        throw MalformedScene(fmt::format("node '{}' refers to mesh {} of {}", node->mName.C_Str(),
                                         index, scene.mNumMeshes));
      }
      const aiMesh& mesh = *scene.mMeshes[index];
      if (mesh.mNumVertices > 0 && mesh.mVertices == nullptr) {
        throw MalformedScene(
            fmt::format("mesh {} has {} vertices but no positions", index, mesh.mNumVertices));
      }
      if (mesh.mNumFaces > 0 && mesh.mFaces == nullptr) {
        throw MalformedScene(
            fmt::format("mesh {} has {} faces but no face list", index, mesh.mNumFaces));
      }
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) {
          ++other_faces;
          continue;
        }
        if (face.mIndices == nullptr) {
          throw MalformedScene(fmt::format("face {} of mesh {} has no indices", f, index));
        }
        for (int c = 0; c < 3; ++c) {
          if (face.mIndices[c] >= mesh.mNumVertices) {
            throw MalformedScene(fmt::format("face {} of mesh {} refers to vertex {} of {}", f,
                                             index, face.mIndices[c], mesh.mNumVertices));
          }
        }
        ++num_triangles;
      }
      num_vertices += mesh.mNumVertices;
      instances.push_back(Instance{&mesh, transform, mirrored});
    }
    if (node->mNumChildren > 0 && node->mChildren == nullptr) {
      throw MalformedScene(fmt::format("node '{}' has {} children but no child list",
                                       node->mName.C_Str(), node->mNumChildren));
    }
    // children pushed last-first, so they are visited in file order (depth first)
    for (unsigned c = node->mNumChildren; c-- > 0;) {
      if (node->mChildren[c] == nullptr) {
        throw MalformedScene(
            fmt::format("child {} of node '{}' is missing", c, node->mName.C_Str()));
      }
      pending.emplace_back(node->mChildren[c], transform);
    }
  }
  // indices travel as int32
  if (num_vertices > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max())) {
    throw MalformedScene(fmt::format("{} vertices: more than the {} a mesh may have", num_vertices,
                                     std::numeric_limits<std::int32_t>::max()));
  }
  return instances;
}

// the header, every instance's vertices in the root frame, then every triangle, re-wound where
// a mirroring transform turned it inward (swapping two corners restores the outward normal)
bool StreamMesh(int fd, const std::vector<Instance>& instances, const ms::Header& header) {
  if (!WriteAll(fd, &header, sizeof(header))) return false;
  std::vector<double> coordinates;
  coordinates.reserve(3 * kChunk);
  for (const Instance& instance : instances) {
    const Eigen::Matrix3d linear = instance.transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d translation = instance.transform.topRightCorner<3, 1>();
    const bool identity = instance.transform == Eigen::Matrix4d::Identity();
    for (unsigned v = 0; v < instance.mesh->mNumVertices; ++v) {
      const aiVector3D& p = instance.mesh->mVertices[v];
      const Eigen::Vector3d q(p.x, p.y, p.z);
      const Eigen::Vector3d r = identity ? q : Eigen::Vector3d(linear * q + translation);
      coordinates.insert(coordinates.end(), {r.x(), r.y(), r.z()});
      if (coordinates.size() == 3 * kChunk) {
        if (!WriteAll(fd, coordinates.data(), coordinates.size() * sizeof(double))) return false;
        coordinates.clear();
      }
    }
  }
  if (!WriteAll(fd, coordinates.data(), coordinates.size() * sizeof(double))) return false;

  std::vector<std::int32_t> indices;
  indices.reserve(3 * kChunk);
  std::int32_t base = 0;
  for (const Instance& instance : instances) {
    const aiMesh& mesh = *instance.mesh;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      const std::int32_t a = base + static_cast<std::int32_t>(face.mIndices[0]);
      const std::int32_t b = base + static_cast<std::int32_t>(face.mIndices[1]);
      const std::int32_t c = base + static_cast<std::int32_t>(face.mIndices[2]);
      if (instance.mirrored) {
        indices.insert(indices.end(), {a, c, b});
      } else {
        indices.insert(indices.end(), {a, b, c});
      }
      if (indices.size() == 3 * kChunk) {
        if (!WriteAll(fd, indices.data(), indices.size() * sizeof(std::int32_t))) return false;
        indices.clear();
      }
    }
    base += static_cast<std::int32_t>(mesh.mNumVertices);
  }
  return WriteAll(fd, indices.data(), indices.size() * sizeof(std::int32_t));
}

// a whole decimal argument in [0, max], or false
bool ParseCount(const char* text, unsigned long long max, unsigned long long& value) {
  if (text == nullptr || *text < '0' || *text > '9') return false;
  errno = 0;
  char* end = nullptr;
  value = std::strtoull(text, &end, 10);
  return errno == 0 && *end == '\0' && value <= max;
}

// lowers `resource` to `soft` (the signal or failure point) and `hard`; an existing lower hard
// limit stays (an unprivileged process cannot raise it)
void SetLimit(int resource, rlim_t soft, rlim_t hard) {
  rlimit limit;
  if (::getrlimit(resource, &limit) != 0) return;
  if (limit.rlim_max != RLIM_INFINITY) hard = std::min(hard, limit.rlim_max);
  limit.rlim_max = hard;
  limit.rlim_cur = std::min(soft, hard);
  ::setrlimit(resource, &limit);
}

int Run(int argc, char** argv) {
  unsigned long long fd = 0, memory = 0, seconds = 0, parent = 0;
  if (argc != 6 || !ParseCount(argv[1], 1 << 20, fd) ||
      !ParseCount(argv[2], std::numeric_limits<rlim_t>::max(), memory) ||
      !ParseCount(argv[3], 1 << 30, seconds) ||
      !ParseCount(argv[4], std::numeric_limits<pid_t>::max(), parent)) {
    std::fprintf(stderr,
                 "usage: ecpsim-mesh-reader OUTPUT_FD MEMORY_BYTES CPU_SECONDS PARENT_PID PATH\n"
                 "(started by ecpsim's LoadMesh; not meant to be run by hand)\n");
    return ms::kExitUsage;
  }
  const int out = static_cast<int>(fd);

  // die with the thread that started us (no orphan keeps reading); it may already be gone
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != static_cast<pid_t>(parent)) return ms::kExitUsage;

  // the limits: address space (a runaway allocation fails with bad_alloc), CPU time (a backstop
  // for the parent's wall-clock deadline), and no core dumps of a crash on a corrupt file
  SetLimit(RLIMIT_AS, static_cast<rlim_t>(memory), static_cast<rlim_t>(memory));
  // SIGXCPU at the soft limit (named in the parent's message), SIGKILL a second later
  SetLimit(RLIMIT_CPU, static_cast<rlim_t>(seconds), static_cast<rlim_t>(seconds) + 1);
  SetLimit(RLIMIT_CORE, 0, 0);

  try {
    // polygons become triangles; every other post-processing step is left out for speed
    // (welding is done by LoadMesh, in double precision)
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(argv[5], aiProcess_Triangulate);
    if (scene == nullptr) {
      const std::string error = importer.GetErrorString();
      // assimp turns exceptions of its importers into error strings, bad_alloc included
      if (error.find("bad_alloc") != std::string::npos) return SendOutOfMemory(out);
      return SendError(out, error.empty() ? "assimp gave no reason" : error);
    }
    ms::Header header = MakeHeader(ms::Kind::kMesh);
    const std::vector<Instance> instances =
        CollectInstances(*scene, header.num_vertices, header.num_triangles, header.other_faces);
    header.num_meshes = scene->mNumMeshes;
    return StreamMesh(out, instances, header) ? ms::kExitOk : ms::kExitReported;
  } catch (const std::bad_alloc&) {
    return SendOutOfMemory(out);
  } catch (const MalformedScene& e) {
    return SendError(out, fmt::format("the file gives a malformed scene: {}", e.what()));
  } catch (const std::exception& e) {
    return SendError(out, e.what());
  }
}

}  // namespace
}  // namespace ecpsim::geometry

int main(int argc, char** argv) { return ecpsim::geometry::Run(argc, argv); }
