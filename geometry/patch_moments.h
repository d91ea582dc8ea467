#pragma once
// Moments of a contact patch under uniform pressure: where its load centre is, how far, on
// average, the patch lies from a point (the torsional arm of its friction, engine/README.md,
// "Patch-aware torsional friction"), and its area moments, on which a uniformly compliant patch's
// elastic energy under a load depends (engine/README.md, "Steps whose solutions form a set").

#include <Eigen/Core>

#include "geometry/contact_patch.h"

namespace ecpsim::geometry {

/// Which of a patch's features carry a uniform pressure: its polygons where they have area; a
/// patch of segments only (an edge, the dumbbell's rims) a uniform line load; a patch of points
/// only an equal load on each. Lower-dimensional features beside higher ones carry nothing (a
/// uniform pressure puts no load on a set of zero area).
enum class PatchLoad { kNone, kArea, kLine, kPoints };

/// The features of `patch` that carry the load (above).
PatchLoad LoadedFeatures(const ContactPatch& patch);

/// The load centre of `patch` (world, on `plane`): the area centroid of its polygons, the length
/// centroid of its segments or the mean of its points, as LoadedFeatures says. Zero for an empty
/// patch. Polygons are taken with their signed areas about `plane.normal`, so a hole traced
/// against its outer loop (ExtractContactPatch's loops) is subtracted.
Eigen::Vector3d PatchCentroid(const ContactPatch& patch, const Plane& plane);

/// The mean in-plane distance (m) of the loaded features of `patch` from `centre` (world;
/// projected on `plane`): ∫|x − centre| dA / A over the polygons, ∫|x − centre| ds / L over the
/// segments, or the mean over the points. Under uniform pressure this is the largest friction
/// moment about `centre` over the largest friction force, μ ∫p|x − c| / μ ∫p. Exact (closed-form
/// integrals per edge, no quadrature): a square of side a about its centre gives
/// a (√2 + asinh 1) / 6 ≈ 0.3826 a, a disc of radius R 2R/3, a segment of length L about its
/// middle L/4, a point 0. Zero for an empty patch.
double PatchMeanDistance(const ContactPatch& patch, const Plane& plane,
                         const Eigen::Vector3d& centre);

/// A patch's area A, centroid and second moments about the centroid along its principal axes
/// (u1, u2 in the plane, I1 ≥ I2 ≥ 0: ∫ (u1·(x − centroid))² dA and ∫ (u2·(x − centroid))² dA).
struct PatchMoments {
  double area = 0;                                     // m²
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world, on the plane
  Eigen::Vector3d u1 = Eigen::Vector3d::UnitX();       // principal axes (unit, world) ...
  Eigen::Vector3d u2 = Eigen::Vector3d::UnitY();
  double I1 = 0, I2 = 0;  // m⁴, ... and the second moments along them
};

/// The area moments of `patch`'s loaded features (LoadedFeatures) on `plane`: its polygons with
/// their signed areas as PatchCentroid takes them (a hole traced against its outer loop is
/// subtracted; the whole patch may turn either way about the normal); a patch of segments as
/// strips, and one of points as squares, of side `width` (m) — a line or a point contact as the
/// limit of a thin patch. Zero area for an empty patch.
PatchMoments MomentsOf(const ContactPatch& patch, const Plane& plane, double width);

}  // namespace ecpsim::geometry
