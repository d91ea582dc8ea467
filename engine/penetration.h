#pragma once
// How deep the bodies' meshes reach into the obstacles: the non-penetration check of a run.

#include <vector>

#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// Measures penetration of every body's *mesh* (not only its ECP) into every obstacle.
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

  /// m, ≥ 0: the largest depth of any mesh vertex of any body inside any obstacle at `state`.
  double MaxDepth(const Scene& scene, const State& state) const;

  /// m, ≥ 0: the largest depth of body `body`'s mesh vertices inside obstacle `obstacle`.
  double Depth(const Scene& scene, const State& state, int body, int obstacle) const;

  /// Per body, the mesh vertex indices checked against half-spaces (for tests).
  const std::vector<std::vector<int>>& half_space_vertices() const { return half_space_vertices_; }

 private:
  std::vector<std::vector<int>> half_space_vertices_;
};

}  // namespace ecpsim::engine
