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

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "geometry/weld_vertices.h"

namespace ecpsim::geometry {
namespace {

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4,  //
      m.b1, m.b2, m.b3, m.b4,   //
      m.c1, m.c2, m.c3, m.c4,   //
      m.d1, m.d2, m.d3, m.d4;
  return e;
}

// appends the triangles of every mesh under `node`, in the root frame (node transforms composed
// in double precision); counts the faces that are points or lines
void CollectTriangles(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent,
                      TriangleMesh& out, std::size_t& other_faces) {
  const Eigen::Matrix4d transform = parent * ToEigen(node.mTransformation);
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int base = static_cast<int>(out.vertices.size());
    out.vertices.reserve(out.vertices.size() + mesh.mNumVertices);
    // node transforms are affine (assimp composes rotations, scalings and translations)
    const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d translation = transform.topRightCorner<3, 1>();
    const bool identity = transform == Eigen::Matrix4d::Identity();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      const Eigen::Vector3d q(p.x, p.y, p.z);
      out.vertices.push_back(identity ? q : Eigen::Vector3d(linear * q + translation));
    }
    out.triangles.reserve(out.triangles.size() + mesh.mNumFaces);
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) {
        ++other_faces;
        continue;
      }
      out.triangles.emplace_back(base + static_cast<int>(face.mIndices[0]),
                                 base + static_cast<int>(face.mIndices[1]),
                                 base + static_cast<int>(face.mIndices[2]));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    CollectTriangles(scene, *node.mChildren[c], transform, out, other_faces);
  }
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

}  // namespace

TriangleMesh LoadMesh(const std::string& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0) {
    throw InputError(fmt::format("{}: scale = {}: expected a finite scale > 0", path, scale));
  }

  // check the file ourselves: assimp's messages for these cases are vague
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    throw InputError(fmt::format("{}: no such mesh file", path));
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw InputError(fmt::format("{}: not a regular file; expected a mesh file", path));
  }
  if (std::filesystem::file_size(path, error) == 0 && !error) {
    throw InputError(fmt::format("{}: empty file; expected a mesh", path));
  }

  // polygons become triangles; every other post-processing step is left out for speed (welding and
  // the transforms are done below, in double precision)
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  if (scene == nullptr) {
    throw InputError(fmt::format("{}: cannot read the mesh: {}", path, importer.GetErrorString()));
  }
  TriangleMesh mesh;
  std::size_t other_faces = 0;
  if (scene->mRootNode != nullptr) {
    CollectTriangles(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), mesh, other_faces);
  }
  if (mesh.triangles.empty()) {
    throw InputError(fmt::format(
        "{}: no triangles in the file ({} meshes, {} point/line primitives); expected a triangle "
        "or polygon surface",
        path, scene->mNumMeshes, other_faces));
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

  // every coordinate finite, before and after scaling
  for (Eigen::Vector3d& v : mesh.vertices) {
    if (!v.allFinite()) {
      throw InputError(fmt::format(
          "{}: a vertex has a non-finite coordinate ({}, {}, {}); expected finite numbers", path,
          v.x(), v.y(), v.z()));
    }
    v *= scale;
    if (!v.allFinite()) {
      throw InputError(fmt::format("{}: scale = {} overflows the coordinates", path, scale));
    }
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
