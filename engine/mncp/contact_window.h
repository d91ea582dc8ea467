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
std::vector<int> SelectWindow(const geometry::ConvexShape& hull, const Eigen::Vector3d& direction_B,
                              int rings, bool use_window);

/// The hull constraints left out of `window` that the point y_B (body frame) violates by more than
/// `tolerance` (m), among the faces incident to the vertices of window constraint `active` — the
/// face y_B was solved on (its largest multiplier). Empty means the windowed solution solves the
/// full MNCP: every constraint left out has f_i(y) ≤ 0 and multiplier 0. Why the neighbourhood
/// suffices: on the plane of face `active`, the hull's facet is cut out by the planes of its
/// neighbours, all of which are incident to its vertices, so a point of that plane outside the
/// facet violates one of them. The test is on the half-spaces themselves, not on the face's
/// vertex polygon: merged coplanar faces make the two differ by up to the merge tolerance (1e-6 of
/// the hull's size), and a solution at a vertex where three merged planes meet sits that far off
/// the polygon while being a genuine solution. Cost O(face size × vertex degree), independent of
/// the hull's size. Smooth primitives and full windows leave nothing out: empty.
std::vector<int> WindowViolations(const geometry::ConvexShape& hull, const std::vector<int>& window,
                                  int active, const Eigen::Vector3d& y_B, double tolerance);

/// Whether y_B (body frame), taken to lie on the plane of face `face`, is on its facet: no face
/// incident to the facet's vertices but `face` itself is violated by more than `tolerance` (m),
/// WindowViolations' test for a window of one face. Allocates nothing.
bool OnFaceFacet(const geometry::PolyhedralShape& hull, int face, const Eigen::Vector3d& y_B,
                 double tolerance);

/// `window` grown around `violated` (sorted, unique): the violated constraints and every face
/// incident to their vertices.
std::vector<int> GrowWindow(const geometry::ConvexShape& hull, const std::vector<int>& window,
                            const std::vector<int>& violated);

}  // namespace ecpsim::engine
