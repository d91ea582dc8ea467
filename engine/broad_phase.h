#pragma once
// The broad phase: per body a world box that holds everything of it that can be touched within
// the step, so that pairs whose boxes are apart stay out of the step's islands.

#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// An axis-aligned box (world frame, m).
using Box = Eigen::AlignedBox3d;

/// What each body can reach within the step [t, t + h], in the scene's order.
struct StepReach {
  /// The body's world box: its hull's box at the start pose grown by `distance` — h (|v| + |ω| r +
  /// |p_applied| / m + h |g|) for its own motion, plus h V_max for what a contact can give it: a
  /// body struck by another, or pushed, ends the step no faster than the fastest body of the scene
  /// (V_max, kinematic ones included) brings in, plus gravity and loads. A kinematic body's box
  /// holds its hull at the step's two ends. A bound that is not finite reaches everything.
  std::vector<Box> boxes;
  /// m: how far any point of the body can move within the step (a jaw's closing included);
  /// infinite for a kinematic body, whose box holds its motion instead.
  std::vector<double> distance;
  /// m: how far any point of the body can move within the step by its own motion, loads and
  /// gravity alone, h (|v| + |ω| r + |p_applied| / m + h |g|) — `distance` without what a contact
  /// can give it; infinite for a kinematic body and a gripper's jaw (driven, not free).
  std::vector<double> own_distance;
  /// m: the diagonal of the hull's box at the start pose, the body's length scale.
  std::vector<double> size;
  /// m/s (world): a jaw's closing speed along its gripper's axis, which grows its box along that
  /// axis only; zero for every other body.
  std::vector<Eigen::Vector3d> closing;
  /// Per body whose contacts may touch its parts (Decomposition kParts or kAuto), each part's
  /// world box grown as the body's; empty for every other body.
  std::vector<std::vector<Box>> part_boxes;
};

/// Every body's reach for the step from `state`, into `reach` over its last contents (reusing
/// their storage: a step allocates nothing once its sizes have been seen).
void StepReachOf(const Scene& scene, const State& state, StepReach& reach);

/// OverlappingBoxes' working storage, kept by the caller from step to step.
struct BoxSweep {
  std::vector<std::pair<double, int>> order;  // (lower x, box), sorted
  std::vector<Box> sorted;                    // the boxes in that order, side by side
};

/// Every pair (i, j), i < j, of `boxes` that intersect (Box::intersects), into `pairs` (in the
/// sweep's order): sweep and prune along x, so that the cost grows with the bodies and the pairs
/// of boxes that overlap along x, not with all pairs. A box with a NaN bound meets none.
void OverlappingBoxes(const std::vector<Box>& boxes, BoxSweep& sweep,
                      std::vector<std::pair<int, int>>& pairs);

/// Whether the bodies of contact pair `k` (between two bodies) can touch within the step: their
/// boxes (and the boxes of the parts it names) overlap and, unless one is kinematic, their hulls
/// (or the parts contact k names) at the step's start come within the sum of their distances
/// (geometry::WithinDistance) — which a pair that carried a normal impulse over the last step does
/// without the test: it touches at the step's start. The hulls' test keeps out pairs whose boxes
/// overlap only because a turned body's box holds more than its hull (a pile turned about z, the
/// dominoes), so that which contacts a step solves does not depend on the world axes.
bool BodiesInReach(const Scene& scene, const State& state, const StepReach& reach, int k);

/// Whether contact pair `k` (between two bodies, in reach: BodiesInReach) stays apart within the
/// step unless a contact of the step pushes one of its bodies: it carried no normal impulse over
/// the last step and its hulls (or the parts it names) at the step's start lie farther apart than
/// the two bodies' own motions can close (StepReach::own_distance). Such a pair between two
/// islands is left out of the step, and the driver verifies at the step's end that it is still
/// apart (EndsApart); engine/README.md, "Pairs apart at both ends of the step".
bool StaysApart(const Scene& scene, const State& state, const StepReach& reach, int k);

/// Whether the sides of contact pair `k` (between two bodies) are strictly apart with its bodies
/// at `body` and `other` (GJK finds a separating direction); `size` (m) the bodies' length scale.
bool EndsApart(const Scene& scene, int k, const BodyState& body, const BodyState& other,
               double size);

/// Whether the box of the part of F that `pair` names (between two bodies, F touching with a
/// part) meets the whole box of G: where it does not, no contact of that part with G can act.
bool PartReachesBody(const StepReach& reach, const ContactPair& pair);

/// Whether anything in `box` can touch the fixed convex `obstacle` (world frame): a half-space's
/// constraint at the box's point deepest into it, else the obstacle's own box.
bool InReach(const Box& box, const geometry::ConvexShape& obstacle);

}  // namespace ecpsim::engine
