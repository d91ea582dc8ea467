#pragma once
// How two bounded convex shapes at given poses lie to each other: the axis that separates them
// best among candidate axes, and how deep they overlap (GJK + EPA on their support functions,
// libccd).

#include <vector>

#include <Eigen/Geometry>

#include "geometry/convex_shape.h"

namespace ecpsim::geometry {

/// m, ≥ 0: the penetration depth of `a` at pose X_a and `b` at X_b (shape frames → world): 0 when
/// they are apart or touch, else the length of the shortest translation of one that separates
/// them: for polyhedra to kPenetrationRelTolerance × `length_scale`; where a curved surface
/// bounds it, low by up to kPenetrationCurvedRelError of it (EPA's polytope is inscribed in the
/// shapes' Minkowski difference). `length_scale` (m, > 0) is the size of the shapes, the unit
/// in which the query is computed, so that it is the same in millimetres or kilometres and free
/// of the round-off of far-from-origin coordinates). Both shapes must be bounded (not a
/// half-space: its support point is at infinity). ECPSIM_DEMAND on a half-space or a
/// non-positive `length_scale`.
double PenetrationDepth(const ConvexShape& a, const Eigen::Isometry3d& X_a, const ConvexShape& b,
                        const Eigen::Isometry3d& X_b, double length_scale);

/// Whether `a` at X_a comes within `distance` (m, ≥ 0) of `b` at X_b: GJK (libccd) on `a` grown
/// by a ball of that radius against `b`, in units of `length_scale` (m, > 0, the shapes' size).
/// False only where GJK finds a direction along which the grown `a` and `b` are apart, or gives
/// up after its iterations, which it does only where they touch to round-off — the shapes then
/// `distance` apart, which either answer is right for. Both shapes must be bounded; ECPSIM_DEMAND
/// on a half-space, a negative distance or a non-positive length scale. An infinite distance
/// reaches everything.
bool WithinDistance(const ConvexShape& a, const Eigen::Isometry3d& X_a, const ConvexShape& b,
                    const Eigen::Isometry3d& X_b, double distance, double length_scale);

/// A unit axis u and the separation of two shapes along it: the gap between b's extent and a's
/// (min over a of u·x − max over b of u·x), > 0 when the axis separates them, < 0 the overlap
/// of their projections (which bounds their penetration depth from above).
struct AxisSeparation {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // world, from b toward a
  double separation = -INFINITY;                    // m
};

/// The separation of `a` at X_a from `b` at X_b along unit `axis` (world, from b toward a).
AxisSeparation SeparationAlong(const ConvexShape& a, const Eigen::Isometry3d& X_a,
                               const ConvexShape& b, const Eigen::Isometry3d& X_b,
                               const Eigen::Vector3d& axis);

/// The candidate axis, either sign, that separates `a` at X_a from `b` at X_b the most: the
/// `hints`, the line of the frames' origins, the world axes and the face normals of whichever
/// shapes are polyhedra. When two polyhedra are apart one of their face normals or an edge
/// pair's cross product separates them (the separating axis theorem), so the result is > 0
/// unless an edge–edge axis alone does; for overlapping polyhedra it is minus the smallest
/// overlap of a face axis (the penetration depth where a vertex or face is deepest). Costs two
/// support queries per candidate: O(faces) hill climbs, meant for a pair's first step, not every
/// step. ECPSIM_DEMAND on a half-space.
AxisSeparation BestSeparatingAxis(const ConvexShape& a, const Eigen::Isometry3d& X_a,
                                  const ConvexShape& b, const Eigen::Isometry3d& X_b,
                                  const std::vector<Eigen::Vector3d>& hints = {});

/// The relative accuracy of PenetrationDepth: EPA stops when the polytope's face nearest the
/// origin advances by less than this (× length_scale). The polytope converges to a curved
/// shape's surface only as the square of its facets' size, so a tighter stop costs many facets
/// on a cylinder or sphere; 1e-6 of the size is far below any depth that matters to a step.
inline constexpr double kPenetrationRelTolerance = 1e-6;

/// How low PenetrationDepth may come out where a curved surface bounds the depth, relative to
/// it: libccd's EPA stops on its own criterion there, measured 5e-4 low for two spheres and 4e-3
/// for a cylinder against a box edge (tests/geometry/convex_separation_test.cpp), with margin.
inline constexpr double kPenetrationCurvedRelError = 1e-2;

}  // namespace ecpsim::geometry
