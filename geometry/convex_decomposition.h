#pragma once
// A solid mesh split into convex parts for contact: the exact pieces, merged where their union
// is convex, each seam between two pieces moved inside one of them.

#include <cstddef>
#include <string>
#include <vector>

#include "geometry/convex_hull.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// How far a part is grown across a seam into the part that covers it, relative to the mesh's
/// bounding-box diagonal: far above round-off, far below any modelled feature (1 mm on a 1 m body),
/// and never deeper than the covering part reaches behind the seam (checked).
inline constexpr double kSeamOverlapRel = 1e-3;

/// The convex parts of the solid a closed, consistently oriented mesh bounds (mesh frame):
/// ExactConvexPieces, then
/// - where `tolerance_rel` is 0, two pieces meeting face to face whose union is convex (its
///   hull's volume their sum, to kCoplanarTolerance) merged, until none are;
/// - else two parts meeting face to face merged, cheapest first (the volume the hull of the two
///   adds: a convex union's nothing), wherever every point of that hull lies within
///   `tolerance_rel` × the diagonal of the solid (ReachesWithin, geometry/hull_reach.h), until
///   none do; a pair refused stays so (a part only grows): a curved, tessellated cavity, whose
///   exact pieces are one per facet of its wall, gives a few parts within that tolerance
///   instead;
/// - each face of a part that the faces of other parts lying on it and facing it cover together
///   (a seam) pushed kSeamOverlapRel × the diagonal into them where they reach so deep behind
///   their shares of it, so that the seam's edges are inside a part, not on the body's surface
///   (geometry/part_seams.h).
/// The parts' union holds the solid and lies within `tolerance_rel` × the diagonal of it (the
/// solid itself where `tolerance_rel` is 0), except where two grown faces of one part meet: the
/// hull of the two prisms fills the wedge between them, at most half the depth across. More
/// than `max_parts` parts throws.
/// @throws InputError naming `source` for a mesh ExactConvexPieces refuses, a `tolerance_rel`
///         not in [0, 1), or more than `max_parts` parts (the message says how many and to
///         raise the tolerance).
std::vector<ConvexHull> DecomposeSolid(const TriangleMesh& mesh, const std::string& source,
                                       std::size_t max_parts, double tolerance_rel);

/// m³: the volume of a convex hull.
double HullVolume(const ConvexHull& hull);

}  // namespace ecpsim::geometry
