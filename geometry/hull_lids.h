#pragma once
// Where a body's convex hull is not its surface: the hull's faces that its convex parts do not
// cover, the lids over its cavities and openings (a cup's rim plane, the span across a handle).
// A body touching the hull away from every lid touches the body itself, so the one hull contact
// is exact there.

#include <memory>
#include <vector>

#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"

namespace ecpsim::geometry {

/// How far (× the hull's diagonal) a lid's slab reaches under the hull's face: a solid for GJK's
/// distance queries, thin against every feature a body can have.
inline constexpr double kLidDepthRel = 1e-3;

/// The indices of the faces of `hull` that the faces of `parts` (convex, in the hull's frame)
/// lying on their planes and facing the same way do not cover together: an uncovered area above
/// `tolerance` × the hull's size (m², `tolerance` in m, `size` the hull's diagonal in m). Parts
/// may overlap one another. In the hull's face order.
std::vector<int> UncoveredFaces(const ConvexHull& hull, const std::vector<const ConvexHull*>& parts,
                                double tolerance, double size);

/// A lid as a solid for distance queries: face `face` of `hull` and its copy `depth` m inside
/// the hull along the face's normal, their hull (the slab under the face).
ConvexHull LidSlab(const ConvexHull& hull, int face, double depth);

/// A body's lids (its frame): LidSlab kLidDepthRel deep under each of UncoveredFaces of `hull`
/// by `parts` (kCoplanarTolerance × the hull's diagonal), where `hull` is not its surface. A
/// smooth part covers nothing; a smooth hull is one lid, itself. Empty where the parts cover the
/// whole hull: the body is convex, or has closed voids only.
std::vector<std::shared_ptr<const ConvexShape>> LidSlabs(
    std::shared_ptr<const ConvexShape> hull,
    const std::vector<std::shared_ptr<const ConvexShape>>& parts);

}  // namespace ecpsim::geometry
