#pragma once
// Where two convex parts of one body meet face to face. Such a seam is inside the body, but its
// edges lie on the body's surface, and there a contact with one part meets the seam face's
// normal too: the contact's normal cone holds a direction no surface of the body has (a cube in
// the corner of a cup whose wall stands on its floor may be pushed into the floor by the wall).
// Parts that reach into each other instead keep every seam inside a part.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "geometry/convex_hull.h"

namespace ecpsim::geometry {

/// A face of one part against a face of another on one plane, facing each other.
struct Seam {
  int face_a = -1;                                   // index into a's faces
  int face_b = -1;                                   // index into b's faces
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the centre of a's face's corners (m)
};

/// Whether face f of `a` and face g of `b` lie on one plane facing each other: offsets within
/// `tolerance` m, normals opposite within `tolerance` over `size` (m, the parts' size).
bool FacesMeet(const ConvexHull& a, int f, const ConvexHull& b, int g, double tolerance,
               double size);

/// Face `face` of `hull` in the coordinates (u, v) of a plane it lies on (u, v orthonormal):
/// its corners, counter-clockwise about u × v.
std::vector<Eigen::Vector2d> FaceInPlane(const ConvexHull& hull, int face, const Eigen::Vector3d& u,
                                         const Eigen::Vector3d& v);

/// The signed area of a polygon (m², > 0 counter-clockwise).
double SignedArea(const std::vector<Eigen::Vector2d>& polygon);

/// The part of convex `polygon` left of the line a → b (`left`) or right of it, on the line
/// included (one Sutherland–Hodgman pass).
std::vector<Eigen::Vector2d> ClipToSide(const std::vector<Eigen::Vector2d>& polygon,
                                        const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                        bool left);

/// The first face of `a` that lies on the plane of a face of `b` with the opposite normal (within
/// `tolerance` m, and normals within `tolerance` over the parts' size) and overlaps it over an
/// area, not only along an edge or at a corner: the two faces overlap by more than `tolerance`
/// along every edge normal of either polygon. Nothing where the parts meet along an edge or at a
/// corner only, are apart, or reach into each other (no face of one on a face of the other).
std::optional<Seam> FindSeam(const ConvexHull& a, const ConvexHull& b, double tolerance);

}  // namespace ecpsim::geometry
