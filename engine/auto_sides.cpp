#include "engine/auto_sides.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/convex_separation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

// whether a lid's world box grown by `own_distance` misses `other_box`, which holds the other's
// hull grown by its own reach (StepReach::boxes): a gap along an axis is then more than both
// reaches, and GJK would find them apart
bool LidOutOfReach(const geometry::ConvexShape& lid, const Isometry3d& X_b, const Box& other_box,
                   double own_distance) {
  const geometry::PolyhedralShape* slab = lid.AsPolyhedron();
  if (slab == nullptr) return false;
  Box box;
  for (const Vector3d& corner : slab->hull().vertices) box.extend(X_b * corner);
  const Vector3d grow = Vector3d::Constant(own_distance);
  return !Box(box.min() - grow, box.max() + grow).intersects(other_box);
}

// whether `other` at X_o reaches into a cavity of `body` at X_b within `distance` (m): near a
// lid, or inside the hull. `other_box` (null for an obstacle) holds the other's hull grown by
// its reach, `own_distance` the body's: lids whose boxes miss it skip GJK
bool ReachesACavity(const Body& body, const Isometry3d& X_b, double size,
                    const geometry::ConvexShape& other, const Isometry3d& X_o, double distance,
                    const Box* other_box, double own_distance) {
  for (const auto& lid : body.lids) {
    if (other_box != nullptr && LidOutOfReach(*lid, X_b, *other_box, own_distance)) continue;
    // (a kinematic other's distance is infinite: within its box, any lid is reached)
    if (geometry::WithinDistance(*lid, X_b, other, X_o, distance, size)) return true;
  }
  // apart from every lid, `other` is wholly inside the hull or wholly outside it: one of its
  // points tells which
  const Vector3d toward = X_o.linear().transpose() * (X_b.translation() - X_o.translation());
  const Vector3d y = X_b.inverse() * (X_o * other.Support(toward));
  double outside = -INFINITY;
  for (int i = 0; i < body.hull->NumConstraints(); ++i)
    outside = std::max(outside, body.hull->Value(i, y));
  return outside < -kInsideHullRelTolerance * size;
}

}  // namespace

bool HullsExact(const Scene& scene, const State& state, const StepReach& reach, int k) {
  const ContactPair& pair = scene.contacts[k];
  const Body& F = scene.bodies[pair.body];
  const double distance =
      reach.distance[pair.body] + (pair.WithBody() ? reach.distance[pair.other_body] : 0.0);
  const Isometry3d X_F = PoseOf(state.bodies[pair.body]);
  const double size_F = reach.size[pair.body];
  if (!pair.WithBody()) {
    return !ReachesACavity(F, X_F, size_F, *scene.obstacles[pair.obstacle].shape,
                           Isometry3d::Identity(), distance, nullptr, distance);
  }
  const Body& G = scene.bodies[pair.other_body];
  const Isometry3d X_G = PoseOf(state.bodies[pair.other_body]);
  const double size_G = reach.size[pair.other_body];
  const auto chooses = [](const Body& body) { return body.decomposition == Decomposition::kAuto; };
  // a kinematic body's reach is its box, which holds its motion, not a distance: its own lids
  // move within the step
  if (G.IsKinematic() && chooses(G)) return false;
  const int f = pair.body, g = pair.other_body;
  return !(chooses(F) && ReachesACavity(F, X_F, size_F, *G.hull, X_G, distance, &reach.boxes[g],
                                        reach.distance[f])) &&
         !(chooses(G) && ReachesACavity(G, X_G, size_G, *F.hull, X_F, distance, &reach.boxes[f],
                                        reach.distance[g]));
}

}  // namespace ecpsim::engine
