#pragma once
// How deep the bodies' meshes reach into the obstacles: the non-penetration check of a run.

#include <vector>

#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// Measures penetration of every body's *mesh* (not only its ECP) into every obstacle, and of
/// the bodies (or their parts) of each contact pair into each other.
/// The depth of a world point x inside an obstacle G = {g_j(x) ≤ 0} is max(0, −max_j g_j(x)):
/// exactly the distance to G's boundary for a polyhedral G (a plane, a box fixture), and to first
/// order for a smooth primitive, whose constraints have unit gradient on the boundary.
/// For a half-space G the depth is linear in x, so its maximum over the mesh is attained at a
/// vertex of the mesh's convex hull: when the body's hull is the polyhedral hull of its mesh, only
/// the hull's vertices are checked there, which is exact. Every other case checks every vertex.
class PenetrationProbe {
 public:
  /// Precomputes, per body, the mesh vertices that can be deepest in a half-space.
  explicit PenetrationProbe(const Scene& scene);

  /// m, ≥ 0: the largest of Depth over every dynamic body and obstacle and of ContactDepth
  /// over every contact pair of two bodies (Scene::contacts; excluded pairs may overlap) at
  /// `state`, but the hulls' contacts of a pair that lists its parts' too (SideChoice::kHulls):
  /// a hull spans the body's cavities, where the other body may be.
  double MaxDepth(const Scene& scene, const State& state) const;

  /// m, ≥ 0: the largest depth of body `body`'s mesh vertices inside obstacle `obstacle`.
  double Depth(const Scene& scene, const State& state, int body, int obstacle) const;

  /// m, ≥ 0: how deep bodies a and b overlap: the smallest overlap of their projections over
  /// the separating-axis candidates — the face normals of both polyhedral hulls, the line of
  /// their reference points, the world axes and `normal` if given (a contact's solved normal) —
  /// using the half-space vertex sets below (a primitive's display mesh). 0 when any candidate
  /// separates them; the exact penetration depth when the deepest overlap is a vertex or a face
  /// against a face (stacked and pushed bodies); never below it (an upper bound) when two edges
  /// cross, and then also possibly > 0 for hulls that touch or are a hair apart along an edge–edge
  /// axis (which the solved contact normal is, during a run).
  double BodyDepth(const Scene& scene, const State& state, int a, int b,
                   const Eigen::Vector3d* normal = nullptr) const;

  /// m, ≥ 0: BodyDepth of contact k's two sides (Scene::contacts[k], between bodies): the
  /// bodies' where it joins their hulls, else the parts' it names (a part's hull vertices, a
  /// primitive part's display mesh).
  double ContactDepth(const Scene& scene, const State& state, int k,
                      const Eigen::Vector3d* normal = nullptr) const;

  /// Per body, the mesh vertex indices checked against half-spaces (for tests).
  const std::vector<std::vector<int>>& half_space_vertices() const { return half_space_vertices_; }

  /// A convex side of a body for the separating-axis test, body frame: vertices whose hull it is
  /// and its face normals (none for a primitive).
  struct ConvexSide {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<Eigen::Vector3d> normals;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the mean of the vertices
  };

 private:
  std::vector<std::vector<int>> half_space_vertices_;
  // per body: [0] its hull's side (the half-space vertices of its mesh), [1 + i] part i's
  std::vector<std::vector<ConvexSide>> sides_;
};

}  // namespace ecpsim::engine
