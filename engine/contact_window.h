#pragma once
// Which hull constraints enter a step's MNCP ("model no more than the scene needs"), and the check
// after the solve that the window did not change the answer.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// The hull constraints around the support feature of `hull` in `direction_B` (body frame):
/// for a polyhedron the faces incident to the support vertex and to `rings` rings of its
/// neighbours (every face when `use_window` is false or rings < 0); for a smooth primitive all
/// its constraints.
std::vector<int> SelectWindow(const geometry::ConvexShape& hull,
                              const Eigen::Vector3d& direction_B, int rings, bool use_window);

/// True if the point y_B (body frame), solved with only the `window` constraints and lying on
/// window constraint `active` (its largest multiplier), is in the full hull: then every constraint
/// left out has f_i(y) ≤ 0 and zero multiplier, so the windowed solution solves the full MNCP.
/// For a polyhedron this is a point-in-polygon test on face `active` (O(face size)); smooth
/// primitives always use every constraint, so they pass.
bool WindowSolutionIsExact(const geometry::ConvexShape& hull, const std::vector<int>& window,
                           int active, const Eigen::Vector3d& y_B, double tolerance);

}  // namespace ecpsim::engine
