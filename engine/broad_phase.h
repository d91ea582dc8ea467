#pragma once
// The broad phase: per body a world box that holds everything of it that can be touched within
// the step, so that pairs whose boxes are apart stay out of the step's islands.

#include <vector>

#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// An axis-aligned box (world frame, m).
using Box = Eigen::AlignedBox3d;

/// Each body's box for the step [t, t + h]: its hull's box at the start pose grown by how far any
/// of its points can move within the step — h (|v| + |ω| r + |p_applied| / m + h |g|) for its
/// own motion, plus h V_max for what a contact can give it: a body struck by another, or pushed,
/// ends the step no faster than the fastest body of the scene (V_max, kinematic ones included)
/// brings in, plus gravity and loads. A kinematic body's box holds its hull at the step's two ends.
/// One box per scene body, in the scene's order; a bound that is not finite reaches everything.
std::vector<Box> StepBoxes(const Scene& scene, const State& state);

/// Whether anything in `box` can touch the fixed convex `obstacle` (world frame): a half-space's
/// constraint at the box's point deepest into it, else the obstacle's own box.
bool InReach(const Box& box, const geometry::ConvexShape& obstacle);

}  // namespace ecpsim::engine
