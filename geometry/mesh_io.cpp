#include "geometry/mesh_io.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>
#include <utility>
#include <vector>

#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Exporter.hpp>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "geometry/mesh_bounds.h"
#include "geometry/mesh_reader_process.h"
#include "geometry/weld_vertices.h"

namespace ecpsim::geometry {
namespace {

// a length for messages; past the double range it says so instead of "inf"
std::string Metres(double length) {
  return std::isfinite(length) ? fmt::format("{:.3g} m", length) : "more than 1.8e308 m";
}

// assimp's exporter id for a file extension; obj without a material library, stl/ply binary
const char* ExportFormat(std::string extension) {
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return "objnomtl";
  if (extension == ".stl") return "stlb";
  if (extension == ".ply") return "plyb";
  return nullptr;
}

// the size of the regular file `path` in bytes; an InputError for a missing, special or empty file
// (assimp's messages for these cases are vague)
std::uintmax_t CheckMeshFile(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    throw InputError(fmt::format("{}: no such mesh file", path));
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw InputError(fmt::format("{}: not a regular file; expected a mesh file", path));
  }
  const std::uintmax_t file_bytes = std::filesystem::file_size(path, error);
  if (error) throw InputError(fmt::format("{}: cannot read the file: {}", path, error.message()));
  if (file_bytes == 0) throw InputError(fmt::format("{}: empty file; expected a mesh", path));
  return file_bytes;
}

void CheckScale(const std::string& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0) {
    throw InputError(fmt::format("{}: scale = {}: expected a finite scale > 0", path, scale));
  }
}

}  // namespace

TriangleMesh LoadMesh(const std::string& path, double scale) {
  CheckScale(path, scale);
  return LoadMesh(path, scale, MeshReaderLimitsForFile(CheckMeshFile(path)));
}

TriangleMesh LoadMesh(const std::string& path, double scale, const MeshReaderLimits& limits) {
  CheckScale(path, scale);
  CheckMeshFile(path);

  // assimp runs in a limited child process: a crash or runaway on a corrupt file is an error
  ImportedMesh imported = ReadMeshInReaderProcess(path, limits);
  TriangleMesh mesh = std::move(imported.mesh);
  if (mesh.triangles.empty()) {
    throw InputError(fmt::format(
        "{}: no triangles in the file ({} meshes, {} point/line primitives); expected a triangle "
        "or polygon surface",
        path, imported.num_meshes, imported.other_faces));
  }

  // vertices no triangle uses (a point cloud beside the surface, a stray NaN) are dropped
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Eigen::Vector3i& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  if (std::find(used.begin(), used.end(), 0) != used.end()) {
    std::vector<int> index(mesh.vertices.size(), -1);
    TriangleMesh compact;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (!used[v]) continue;
      index[v] = static_cast<int>(compact.vertices.size());
      compact.vertices.push_back(mesh.vertices[v]);
    }
    compact.triangles = std::move(mesh.triangles);
    for (Eigen::Vector3i& t : compact.triangles)
      t = Eigen::Vector3i(index[t[0]], index[t[1]], index[t[2]]);
    mesh = std::move(compact);
  }

  // every coordinate finite (node transforms may overflow what the file stores)
  for (const Eigen::Vector3d& v : mesh.vertices) {
    if (!v.allFinite()) {
      throw InputError(
          fmt::format("{}: a vertex has a non-finite coordinate ({}, {}, {}) after the file's node "
                      "transforms; expected finite numbers",
                      path, v.x(), v.y(), v.z()));
    }
  }

  // the scaled mesh within the size range every later step computes without overflow or
  // underflow (the bounds of the unscaled mesh, scaled: no overflow on the way)
  const MeshBounds file_bounds = ComputeMeshBounds(mesh.vertices);
  if (file_bounds.diagonal == 0.0) {
    throw InputError(fmt::format(
        "{}: all {} vertices coincide (a bounding-box diagonal of 0); expected a surface", path,
        mesh.vertices.size()));
  }
  MeshBounds bounds;
  bounds.diagonal = scale * file_bounds.diagonal;
  bounds.max_abs = scale * file_bounds.max_abs;
  if (!IsInSupportedSizeRange(bounds)) {
    throw InputError(fmt::format(
        "{}: scale = {:g} makes the mesh {} across (bounding-box diagonal; largest |coordinate| "
        "{}); expected {}: choose a scale that converts the file's units to metres",
        path, scale, Metres(bounds.diagonal), Metres(bounds.max_abs), SupportedSizeRangeText()));
  }
  if (scale != 1.0) {
    for (Eigen::Vector3d& v : mesh.vertices) v *= scale;
  }

  TriangleMesh welded = WeldVertices(mesh, DefaultWeldTolerance(mesh));
  if (welded.triangles.empty()) {
    throw InputError(fmt::format(
        "{}: all {} triangles are degenerate (zero area after welding); expected a surface", path,
        mesh.triangles.size()));
  }
  return welded;
}

void SaveMesh(const TriangleMesh& mesh, const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  const char* format = ExportFormat(extension);
  if (format == nullptr) {
    throw InputError(fmt::format("{}: unknown mesh extension '{}'; expected .obj, .stl or .ply",
                                 path, extension));
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw InputError(
          fmt::format("{}: vertex {} has a non-finite coordinate; not written", path, i));
    }
  }

  // a one-mesh, one-material scene (the exporters expect a material); aiScene owns everything
  aiScene scene;
  scene.mRootNode = new aiNode();
  scene.mNumMaterials = 1;
  scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene.mNumMeshes = 1;
  scene.mMeshes = new aiMesh* [1] { new aiMesh() };
  scene.mRootNode->mNumMeshes = 1;
  scene.mRootNode->mMeshes = new unsigned[1]{0};

  aiMesh& out = *scene.mMeshes[0];
  out.mMaterialIndex = 0;
  out.mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  out.mNumVertices = static_cast<unsigned>(mesh.vertices.size());
  out.mVertices = new aiVector3D[mesh.vertices.size()];
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    out.mVertices[i] = aiVector3D(static_cast<ai_real>(v.x()), static_cast<ai_real>(v.y()),
                                  static_cast<ai_real>(v.z()));
  }
  out.mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  out.mFaces = new aiFace[mesh.triangles.size()];
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Eigen::Vector3i& t = mesh.triangles[f];
    ECPSIM_DEMAND(t.minCoeff() >= 0 && t.maxCoeff() < static_cast<int>(mesh.vertices.size()));
    out.mFaces[f].mNumIndices = 3;
    out.mFaces[f].mIndices = new unsigned[3]{
        static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]), static_cast<unsigned>(t[2])};
  }

  // export to memory, then write the bytes atomically ourselves
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, format);
  if (blob == nullptr) {
    throw InputError(
        fmt::format("{}: cannot export the mesh: {}", path, exporter.GetErrorString()));
  }
  WriteFileAtomically(path, std::string_view(static_cast<const char*>(blob->data), blob->size));
}

}  // namespace ecpsim::geometry
