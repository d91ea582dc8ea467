#pragma once
// The actual contact patch between a posed mesh and a plane, for display and tests.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

enum class ContactMode {
  kNone,
  kPoint,           // one isolated point
  kTwoPoint,        // two separated points (a segment's ends but not the segment)
  kMultiPoint,      // three or more isolated points, not all on one line
  kLine,            // one segment (or touching collinear segments)
  kNonConvexLine,   // collinear segments/points with gaps (the dumbbell's two rims)
  kConvexPatch,     // faces whose union is convex (area = hull area)
  kNonConvexPatch,  // faces (and possibly segments/points) whose hull is larger than their union
};

/// "none", "point", "two-point", "multi-point", "line", "non-convex line", "convex patch",
/// "non-convex patch".
const char* ContactModeName(ContactMode mode);

/// A plane n · x = offset bounding G = {x : n · x ≤ offset}; n is unit and points out of G.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0;
};

/// The features of a mesh within a tolerance of the plane, in world coordinates on the plane.
struct ContactPatch {
  std::vector<std::vector<Eigen::Vector3d>> polygons;    // faces lying on the plane
  std::vector<std::array<Eigen::Vector3d, 2>> segments;  // edges on the plane, not in a face
  std::vector<Eigen::Vector3d> points;                   // vertices on it, not in an edge
  std::vector<Eigen::Vector3d> hull;  // 2-D convex hull of all of the above, ccw about n
  double area = 0;                    // m², of `hull` (0 for a point or a segment)
  double feature_area = 0;            // m², of the union of `polygons`
  ContactMode mode = ContactMode::kNone;
};

/// The default distance tolerance as a fraction of the mesh's bounding-box diagonal: 1 µm on a
/// 1 m body — far above the solver's position error (1e-12 of the body's size) and the
/// single-precision rounding of mesh files (6e-8), far below any modelled feature; relative, so
/// that a millimetre part and a 100 m hull find the same patches.
inline constexpr double kContactPatchRelTolerance = 1e-6;  // dimensionless

/// kContactPatchRelTolerance × the bounding-box diagonal of `mesh` (m).
double ContactPatchTolerance(const TriangleMesh& mesh);

/// Extracts the contact patch of `mesh` (body frame) posed by `X_WB` against `plane` (world):
/// every vertex with signed distance ≤ `tolerance` (m) counts as touching; edges and triangles
/// whose vertices all touch become segments and polygons (coplanar triangles merged).
ContactPatch ExtractContactPatch(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WB,
                                 const Plane& plane, double tolerance);

/// Where two bodies touch each other: the part of `patch` (one body's features, extracted on
/// `plane`) that lies in the hull of `other` (the other body's features on the same plane, its
/// normal either way). Polygons and segments are clipped to `other`'s hull (a convex polygon, a
/// segment or a point), so a T-shaped face on a box's larger top keeps its T and a box's face on
/// a narrower one is cut to the overlap; points are kept where the hull holds them within
/// `tolerance` (m), which also decides the result's mode as in ExtractContactPatch.
ContactPatch IntersectContactPatches(const ContactPatch& patch, const ContactPatch& other,
                                     const Plane& plane, double tolerance);

/// As above with the default tolerance ContactPatchTolerance(mesh).
ContactPatch ExtractContactPatch(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WB,
                                 const Plane& plane);

/// True if `point` (world, on the plane) lies in the patch's convex hull within `tolerance` metres.
bool PatchHullContains(const ContactPatch& patch, const Plane& plane, const Eigen::Vector3d& point,
                       double tolerance);

}  // namespace ecpsim::geometry
