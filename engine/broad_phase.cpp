#include "engine/broad_phase.h"

#include <algorithm>
#include <cmath>

#include "engine/loads.h"
#include "geometry/convex_separation.h"

namespace ecpsim::engine {
namespace {

// the broad phase's margin beyond a body's reach in the step, relative to its hull's size: the
// reach is a bound already; the margin only keeps round-off of the support queries out
constexpr double kBroadPhaseRelMargin = 1e-6;

// below this many vertices a polyhedron's world box is cheaper from its vertices than from six
// support queries (a box part has 8)
constexpr size_t kFewVertices = 16;

// the world box of `hull` at pose (c, R): six support queries (hill climbing on a polyhedron), or
// its vertices where it has few
Box HullBox(const geometry::ConvexShape& hull, const Eigen::Vector3d& c, const Eigen::Matrix3d& R) {
  Box box;
  const auto* polyhedron = hull.AsPolyhedron();
  if (polyhedron != nullptr && !polyhedron->hull().vertices.empty() &&
      polyhedron->hull().vertices.size() <= kFewVertices) {
    for (const Eigen::Vector3d& v : polyhedron->hull().vertices) box.extend(c + R * v);
    return box;
  }
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(i);
    box.extend(c + R * hull.Support(R.transpose() * axis));
    box.extend(c + R * hull.Support(R.transpose() * -axis));
  }
  return box;
}

// How far a jaw can move within the step: its gripper holds it on the frame across the axis and
// in orientation (to the frame's pose at the step's end: the displacement and turn over the
// step), and along the axis it moves at its own speed plus the actuator's push h F / m — a
// motion along the axis only (the jaws hang 2.5 cm over the table in scenes/gripper.yaml: an
// isotropic 1 cm of closing would bring the table into the island)
struct JawReach {
  double speed = 0;                                   // m/s, in any direction
  Eigen::Vector3d closing = Eigen::Vector3d::Zero();  // m/s, along the axis (world)
};

JawReach JawReachOf(const Scene& scene, int b, const State& state, double radius,
                    const Eigen::Matrix<double, 6, 1>& applied) {
  const Gripper& gripper = scene.grippers[scene.bodies[b].gripper];
  const int j = gripper.jaws[0] == b ? 0 : 1;
  const double h = scene.h;
  const Body& body = scene.bodies[b];
  const BodyState& s = state.bodies[b];
  const KinematicPose frame = gripper.motion->PoseAt(state.t + h);
  const Eigen::Vector3d axis = ClosingAxis(gripper, frame);
  // across the axis to its place on the frame; along it, with the jaws' midpoint to the frame's
  // centre (island_gripper.h), the jaw's own opening being free
  const KinematicPose target = JawOnFrame(gripper, j, frame);
  const Eigen::Vector3d across = target.p - s.p_WB;
  const Eigen::Vector3d centre_shift =
      0.5 * (target.p + JawOnFrame(gripper, 1 - j, frame).p - state.bodies[gripper.jaws[0]].p_WB -
             state.bodies[gripper.jaws[1]].p_WB);
  const double turn = target.q.angularDistance(s.Q_WB);
  JawReach reach;
  reach.speed = ((across - axis.dot(across) * axis).norm() + std::abs(axis.dot(centre_shift)) +
                 turn * radius) /
                    h +
                std::abs(axis.dot(s.v_WB)) + applied.head<3>().norm() / body.mass +
                h * scene.gravity.norm();
  reach.closing = (h * std::abs(gripper.force(state.t)) / body.mass) * axis;
  return reach;
}

// whether the sides of `pair` with its bodies at `body` and `other` come within `distance` (m;
// GJK in units of `size`, the bodies' length scale)
bool SidesWithin(const Scene& scene, const ContactPair& pair, const BodyState& body,
                 const BodyState& other, double distance, double size) {
  return geometry::WithinDistance(ShapeOfBody(scene, pair), PoseOf(body), ShapeOfOther(scene, pair),
                                  PoseOf(other), distance, size);
}

}  // namespace

void StepReachOf(const Scene& scene, const State& state, StepReach& reach) {
  const double h = scene.h;
  const size_t n = scene.bodies.size();
  std::vector<Box>& boxes = reach.boxes;
  boxes.clear();
  // each body's speed bound first, its distance once the fastest body's is known
  std::vector<double>& speed = reach.distance;
  speed.assign(n, 0.0);
  std::vector<Eigen::Vector3d>& closing = reach.closing;
  closing.assign(n, Eigen::Vector3d::Zero());
  reach.size.resize(n);
  reach.own_distance.resize(n);
  reach.part_boxes.resize(n);
  double fastest = 0;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const BodyState& s = state.bodies[b];
    const Eigen::Matrix3d R = s.Q_WB.toRotationMatrix();
    boxes.push_back(HullBox(*body.hull, s.p_WB, R));
    std::vector<Box>& parts = reach.part_boxes[b];
    parts.clear();
    if (body.decomposition != Decomposition::kNone) {
      for (const auto& part : body.parts) parts.push_back(HullBox(*part, s.p_WB, R));
    }
    const double radius =
        0.5 * boxes.back().diagonal().norm() + (boxes.back().center() - s.p_WB).norm();
    if (body.IsKinematic()) {
      const KinematicPose end = body.motion->PoseAt(state.t + h);
      boxes.back().extend(HullBox(*body.hull, end.p, end.q.toRotationMatrix()));
      for (size_t i = 0; i < parts.size(); ++i)
        parts[i].extend(HullBox(*body.parts[i], end.p, end.q.toRotationMatrix()));
      speed[b] = 0;
      fastest = std::max(fastest, (end.p - s.p_WB).norm() / h + s.w_WB.norm() * radius);
      continue;
    }
    const Eigen::Matrix<double, 6, 1> applied =
        AppliedImpulse(scene.loads, scene.impulses, static_cast<int>(b), state.t, h, R);
    if (body.IsJaw()) {
      const JawReach jaw = JawReachOf(scene, static_cast<int>(b), state, radius, applied);
      speed[b] = jaw.speed;
      closing[b] = jaw.closing;
    } else {
      speed[b] = s.v_WB.norm() + s.w_WB.norm() * radius + applied.head<3>().norm() / body.mass +
                 h * scene.gravity.norm();
    }
    // a body struck by a jaw can get its closing speed in any direction
    fastest = std::max(fastest, speed[b] + closing[b].norm());
  }
  for (size_t b = 0; b < boxes.size(); ++b) {
    const double size = boxes[b].diagonal().norm();
    const double isotropic = h * (speed[b] + fastest) + kBroadPhaseRelMargin * size;
    Eigen::Array3d grow = h * closing[b].cwiseAbs().array() + isotropic;
    // a bound that overflowed (or is NaN) bounds nothing: the box then reaches everything, so a
    // contact is never missed
    if (!grow.allFinite()) grow.setConstant(INFINITY);
    boxes[b].min().array() -= grow;
    boxes[b].max().array() += grow;
    for (Box& part : reach.part_boxes[b]) {
      part.min().array() -= grow;
      part.max().array() += grow;
    }
    double distance = isotropic + h * closing[b].norm();
    if (scene.bodies[b].IsKinematic() || !std::isfinite(distance)) distance = INFINITY;
    const bool driven = scene.bodies[b].IsKinematic() || scene.bodies[b].IsJaw();
    reach.own_distance[b] = driven ? INFINITY : h * speed[b] + kBroadPhaseRelMargin * size;
    reach.distance[b] = distance;
    reach.size[b] = size;
  }
}

void OverlappingBoxes(const std::vector<Box>& boxes, BoxSweep& sweep,
                      std::vector<std::pair<int, int>>& pairs) {
  std::vector<std::pair<double, int>>& order = sweep.order;
  order.clear();
  pairs.clear();
  for (size_t b = 0; b < boxes.size(); ++b) {
    if (!boxes[b].min().hasNaN() && !boxes[b].max().hasNaN())
      order.emplace_back(boxes[b].min().x(), static_cast<int>(b));
  }
  // by the boxes' lower x, ties by index: every box that meets box i along x and comes after it
  // starts before i's upper x; the boxes copied in that order, so the sweep reads them in turn
  std::sort(order.begin(), order.end());
  sweep.sorted.resize(order.size());
  for (size_t s = 0; s < order.size(); ++s) sweep.sorted[s] = boxes[order[s].second];
  const std::vector<Box>& sorted = sweep.sorted;
  for (size_t s = 0; s < sorted.size(); ++s) {
    const Box& box = sorted[s];
    for (size_t t = s + 1; t < sorted.size() && sorted[t].min().x() <= box.max().x(); ++t) {
      if (!box.intersects(sorted[t])) continue;
      const int i = order[s].second, j = order[t].second;
      pairs.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
}

bool BodiesInReach(const Scene& scene, const State& state, const StepReach& reach, int k) {
  const ContactPair& pair = scene.contacts[k];
  const int a = pair.body, b = pair.other_body;
  if (!reach.boxes[a].intersects(reach.boxes[b])) return false;
  // the parts' own boxes (a part the body's decomposition does not use has none: the hull's)
  const auto box_of = [&](int body, int part) -> const Box& {
    const std::vector<Box>& parts = reach.part_boxes[body];
    return part >= 0 && static_cast<size_t>(part) < parts.size() ? parts[part] : reach.boxes[body];
  };
  if ((pair.part >= 0 || pair.other_part >= 0) &&
      !box_of(a, pair.part).intersects(box_of(b, pair.other_part)))
    return false;
  const double distance = reach.distance[a] + reach.distance[b];
  if (!std::isfinite(distance)) return true;
  // a pair that carried a load touches at the step's start: GJK would say so too, at a cost paid
  // on every step of a pile
  if (static_cast<size_t>(k) < state.contacts.size() && state.contacts[k].p_n > 0) return true;
  return SidesWithin(scene, pair, state.bodies[a], state.bodies[b], distance,
                     std::max(reach.size[a], reach.size[b]));
}

bool StaysApart(const Scene& scene, const State& state, const StepReach& reach, int k) {
  const ContactPair& pair = scene.contacts[k];
  const int a = pair.body, b = pair.other_body;
  if (static_cast<size_t>(k) >= state.contacts.size() || !(state.contacts[k].p_n == 0))
    return false;
  const double distance = reach.own_distance[a] + reach.own_distance[b];
  if (!std::isfinite(distance)) return false;
  return !SidesWithin(scene, pair, state.bodies[a], state.bodies[b], distance,
                      std::max(reach.size[a], reach.size[b]));
}

bool EndsApart(const Scene& scene, int k, const BodyState& body, const BodyState& other,
               double size) {
  return !SidesWithin(scene, scene.contacts[k], body, other, 0, size);
}

bool PartReachesBody(const StepReach& reach, const ContactPair& pair) {
  const std::vector<Box>& parts = reach.part_boxes[pair.body];
  if (pair.part < 0 || static_cast<size_t>(pair.part) >= parts.size()) return true;
  return parts[pair.part].intersects(reach.boxes[pair.other_body]);
}

bool InReach(const Box& box, const geometry::ConvexShape& obstacle) {
  if (!box.min().allFinite() || !box.max().allFinite()) return true;
  const Eigen::Vector3d centre = box.center(), half = 0.5 * box.sizes();
  if (obstacle.IsHalfSpace()) {
    const Eigen::Vector3d g = obstacle.Gradient(0, centre);
    return obstacle.Value(0, centre) - g.cwiseAbs().dot(half) <= 0;
  }
  Box reach;
  for (int i = 0; i < 3; ++i) {
    reach.extend(obstacle.Support(Eigen::Vector3d::Unit(i)));
    reach.extend(obstacle.Support(-Eigen::Vector3d::Unit(i)));
  }
  return reach.intersects(box);
}

}  // namespace ecpsim::engine
