#pragma once
// Moments of a contact patch under uniform pressure: where its load centre is and how far, on
// average, the patch lies from a point (the torsional arm of its friction, engine/README.md,
// "Patch-aware torsional friction").

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

}  // namespace ecpsim::geometry
