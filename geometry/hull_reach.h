#pragma once
// How far a convex hull reaches out of a solid: the check that a part merged from pieces of the
// solid stays within a stated distance of it (an approximate convex decomposition).

#include <vector>

#include "geometry/convex_hull.h"

namespace ecpsim::geometry {

/// The finest cells of ReachesWithin's octree, in half-diagonal, as a fraction of the bound: a
/// cell is accepted when every point of it is provably within the bound, so the finer the cells,
/// the closer to the bound a hull may reach and be accepted (at an eighth, a box reaching less
/// than 2/3 of the bound always is, see ReachesWithin), and the more cells a hull near the bound
/// costs (their number grows as the inverse square of this, over the hull's surface).
inline constexpr double kReachCellRel = 1.0 / 8;

/// Whether every point of `hull` (its volume, not only its surface; mesh frame, m) lies within
/// `bound` m (> 0) of the solid that the closed mesh `mesh` bounds and `solid` measures, given
/// that every point of each of `known` does (convex hulls checked before, e.g. the parts merged
/// into `hull`), one of which lies in the solid.
/// First, at once: where every triangle of the mesh lies beyond or on one of the hull's face
/// planes (within kCoplanarTolerance of the hull's diagonal, the round-off of the exact pieces'
/// vertices), the surface does not enter the hull, which then lies in the solid. Else
/// an octree over the hull's bounding cube, each cell tested at its centre with the distance's
/// 1-Lipschitz bound: a cell is done when it lies outside one of the hull's face planes, inside
/// one of `known`, within `bound` of the solid's surface at every point (distance at the centre +
/// half-diagonal ≤ bound), or inside the solid (centre inside, its distance ≥ the
/// half-diagonal); it proves the hull out of reach when its centre is in the hull and out of the
/// solid by more than `bound` + its half-diagonal; else it is halved, down to cells of
/// kReachCellRel × `bound`, where a cell still undecided refuses the hull. So true means every
/// point is within `bound` (never more, whatever the hull); false means some point may be
/// within a few finest cells of it (an undecided cell's centre is farther than `bound` less its
/// half-diagonal from the solid, and within the hull's face planes grown by that half-diagonal:
/// for a box, within √3 of it from the hull).
bool ReachesWithin(const ConvexHull& hull, const std::vector<const ConvexHull*>& known,
                   const TriangleMesh& mesh, const SolidDistance& solid, double bound);

}  // namespace ecpsim::geometry
