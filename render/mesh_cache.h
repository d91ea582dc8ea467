#pragma once
// GPU copies of triangle meshes, made once per mesh object and reused across frames.

#include <memory>
#include <unordered_map>

#include <Eigen/Core>

#include "geometry/triangle_mesh.h"

namespace ecpsim::render {

/// A mesh in GPU buffers: interleaved position + normal (float) and triangle indices; a corner's
/// normal is the average over the faces at its vertex that meet its face at less than a crease
/// angle, and corners with the same vertex and normal share one GPU vertex.
class GpuMesh {
 public:
  explicit GpuMesh(const geometry::TriangleMesh& mesh);
  ~GpuMesh();
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  /// Draws the triangles with the current program (attributes 0 = position, 1 = normal). A
  /// closed, outward-wound mesh is drawn with back faces culled (they are hidden by its front
  /// faces from any eye outside it, and skipping them halves the triangle setup); any other mesh
  /// is drawn two-sided.
  void Draw() const;

  /// Whether every edge joins exactly two triangles that traverse it in opposite directions and
  /// the enclosed volume is positive (counter-clockwise seen from outside).
  bool closed_outward() const { return closed_outward_; }

  /// Number of triangles drawn (each one once, whether culled or not).
  int triangle_count() const { return index_count_ / 3; }

  /// A sphere around all vertices, in the mesh's frame (m).
  const Eigen::Vector3d& centre() const { return centre_; }
  double radius() const { return radius_; }

 private:
  unsigned vao_ = 0, vbo_ = 0, ibo_ = 0;
  int index_count_ = 0;
  bool closed_outward_ = false;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double radius_ = 0;
};

/// Meshes keyed by object: an entry lives while its mesh is alive (tracked by a weak pointer) and
/// has been used within the last kMaxIdleFrames frames. Needs a current GlContext.
class MeshCache {
 public:
  /// The GPU copy of `*mesh`, uploaded on first use. `mesh` must not be null and must not be
  /// modified while shared with the cache.
  const GpuMesh& Get(const std::shared_ptr<const geometry::TriangleMesh>& mesh);

  /// Ends a frame: frees entries whose mesh died or that went unused for kMaxIdleFrames frames.
  void EndFrame();

  int size() const { return static_cast<int>(entries_.size()); }

  // long enough to survive a toggle or a skipped body, short enough to bound memory
  static constexpr long kMaxIdleFrames = 30;

 private:
  struct Entry {
    std::weak_ptr<const geometry::TriangleMesh> owner;
    std::unique_ptr<GpuMesh> gpu;
    long last_used = 0;
  };
  std::unordered_map<const geometry::TriangleMesh*, Entry> entries_;
  long frame_ = 0;
};

}  // namespace ecpsim::render
