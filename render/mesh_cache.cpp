#include "render/mesh_cache.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

// faces meeting at a vertex within this angle share a smooth normal; sharper edges stay creased
// (the desk's 90° edges are sharp, the dumbbell's 3.75° facets are smooth)
constexpr double kCreaseCos = 0.8;  // cos(≈ 37°)

// True if each directed edge occurs once and its reverse once (a closed, consistently wound
// surface) and the signed volume is positive (outward winding).
bool IsClosedOutward(const geometry::TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return false;
  std::vector<std::pair<int, int>> directed;
  directed.reserve(mesh.triangles.size() * 3);
  double six_volume = 0;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) directed.emplace_back(t[k], t[(k + 1) % 3]);
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  std::sort(directed.begin(), directed.end());
  if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) return false;
  for (const auto& [a, b] : directed) {
    if (a == b || !std::binary_search(directed.begin(), directed.end(), std::make_pair(b, a))) {
      return false;
    }
  }
  return six_volume > 0;
}

}  // namespace

GpuMesh::GpuMesh(const geometry::TriangleMesh& mesh) {
  const auto& V = mesh.vertices;
  const auto& T = mesh.triangles;

  // face normals, area-weighted, and the faces around each vertex
  std::vector<Eigen::Vector3d> face_normals(T.size());
  std::vector<std::vector<int>> vertex_faces(V.size());
  for (size_t f = 0; f < T.size(); ++f) {
    for (int k = 0; k < 3; ++k) ECPSIM_DEMAND(T[f][k] >= 0 && T[f][k] < static_cast<int>(V.size()));
    face_normals[f] = (V[T[f][1]] - V[T[f][0]]).cross(V[T[f][2]] - V[T[f][0]]);
    for (int k = 0; k < 3; ++k) vertex_faces[T[f][k]].push_back(static_cast<int>(f));
  }

  // corners share a GPU vertex when they share a mesh vertex and their crease-limited normal:
  // a smooth 100k-triangle mesh then has ~50k vertices to shade instead of 300k
  std::vector<float> data;
  std::vector<std::uint32_t> indices;
  indices.reserve(T.size() * 3);
  std::vector<std::vector<std::pair<Eigen::Vector3f, std::uint32_t>>> emitted(V.size());
  for (size_t f = 0; f < T.size(); ++f) {
    const double length = face_normals[f].norm();
    const Eigen::Vector3d n_f =
        length > 0 ? Eigen::Vector3d(face_normals[f] / length) : Eigen::Vector3d::UnitZ();
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      for (int g : vertex_faces[T[f][k]]) {
        const double length_g = face_normals[g].norm();
        if (length_g > 0 && face_normals[g].dot(n_f) > kCreaseCos * length_g) n += face_normals[g];
      }
      const Eigen::Vector3f normal =
          (n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : n_f).cast<float>();
      auto& candidates = emitted[T[f][k]];
      const auto same = std::find_if(candidates.begin(), candidates.end(),
                                     [&](const auto& c) { return c.first == normal; });
      if (same != candidates.end()) {
        indices.push_back(same->second);
        continue;
      }
      const auto index = static_cast<std::uint32_t>(data.size() / 6);
      const Eigen::Vector3d& p = V[T[f][k]];
      data.insert(data.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(p.z()), normal.x(), normal.y(), normal.z()});
      candidates.emplace_back(normal, index);
      indices.push_back(index);
    }
  }
  index_count_ = static_cast<int>(indices.size());
  closed_outward_ = IsClosedOutward(mesh);

  // bounding sphere about the box centre
  if (!V.empty()) {
    Eigen::Vector3d lo = V[0], hi = V[0];
    for (const auto& p : V) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    centre_ = 0.5 * (lo + hi);
    for (const auto& p : V) radius_ = std::max(radius_, (p - centre_).norm());
  }

  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(1, &vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glGenBuffers(1, &ibo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
}

GpuMesh::~GpuMesh() {
  glDeleteBuffers(1, &ibo_);
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
}

void GpuMesh::Draw() const {
  if (closed_outward_) {
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
  } else {
    glDisable(GL_CULL_FACE);
  }
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  glDisable(GL_CULL_FACE);
}

const GpuMesh& MeshCache::Get(const std::shared_ptr<const geometry::TriangleMesh>& mesh) {
  ECPSIM_DEMAND(mesh != nullptr);
  auto it = entries_.find(mesh.get());
  // an address reused by a new mesh after the old one died is a different mesh
  if (it != entries_.end() && it->second.owner.lock() != mesh) {
    entries_.erase(it);
    it = entries_.end();
  }
  if (it == entries_.end()) {
    Entry entry;
    entry.owner = mesh;
    entry.gpu = std::make_unique<GpuMesh>(*mesh);
    it = entries_.emplace(mesh.get(), std::move(entry)).first;
  }
  it->second.last_used = frame_;
  return *it->second.gpu;
}

void MeshCache::EndFrame() {
  for (auto it = entries_.begin(); it != entries_.end();) {
    const bool stale =
        it->second.owner.expired() || frame_ - it->second.last_used >= kMaxIdleFrames;
    it = stale ? entries_.erase(it) : std::next(it);
  }
  ++frame_;
}

}  // namespace ecpsim::render
