#include "engine/scene.h"

#include <cmath>
#include <memory>
#include <utility>
#include <variant>

#include "common/errors.h"

namespace ecpsim::engine {

const char* ContactModelName(ContactModel model) {
  switch (model) {
    case ContactModel::kAuto:
      return "auto";
    case ContactModel::kHull:
      return "hull";
    case ContactModel::kPlanar:
      return "planar";
    case ContactModel::kMultiPatch:
      return "multipatch";
    case ContactModel::kPoint:
      return "point";
  }
  return "unknown";
}

const char* SelectionName(Selection selection) {
  switch (selection) {
    case Selection::kCreep:
      return "creep";
    case Selection::kLeastEnergy:
      return "least_energy";
  }
  return "unknown";
}

Friction PairFriction(const Friction& a, const Friction& b) {
  Friction f;
  f.mu = std::sqrt(a.mu * b.mu);
  f.e_t = std::sqrt(a.e_t * b.e_t);
  f.e_o = std::sqrt(a.e_o * b.e_o);
  f.e_r = std::sqrt(a.e_r * b.e_r);
  f.e_r_patch = a.e_r_patch || b.e_r_patch;
  return f;
}

const char* DecompositionName(Decomposition decomposition) {
  switch (decomposition) {
    case Decomposition::kNone:
      return "none";
    case Decomposition::kParts:
      return "parts";
    case Decomposition::kAuto:
      return "auto";
  }
  return "unknown";
}

namespace {

// the sides a body's contacts touch where it touches with its parts (`parts`) or with its hull:
// -1 (the hull) alone, or each of its parts; a body that lists parts to touch with
// (Decomposition::kParts) always takes them, one without parts always its hull
std::vector<int> ContactParts(const Body& body, bool parts) {
  if (body.parts.empty() || body.decomposition == Decomposition::kNone ||
      (body.decomposition == Decomposition::kAuto && !parts)) {
    return {-1};
  }
  std::vector<int> indices(body.parts.size());
  for (size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<int>(i);
  return indices;
}

// each side of F against each side of G, as one pair group's `sides` choice
void AddSidePairs(Scene& scene, ContactPair pair, SideChoice sides) {
  const bool parts = sides != SideChoice::kHulls;
  const std::vector<int> other_parts =
      pair.WithBody() ? ContactParts(scene.bodies[pair.other_body], parts) : std::vector<int>{-1};
  pair.sides = sides;
  for (int part : ContactParts(scene.bodies[pair.body], parts)) {
    for (int other_part : other_parts) {
      pair.part = part;
      pair.other_part = other_part;
      scene.contacts.push_back(pair);
    }
  }
}

// the pair's contacts: both sets where a body chooses per step (Decomposition::kAuto)
void AddSides(Scene& scene, const ContactPair& pair) {
  const auto chooses = [&](int b) {
    return b >= 0 && scene.bodies[b].decomposition == Decomposition::kAuto &&
           !scene.bodies[b].parts.empty();
  };
  if (!chooses(pair.body) && !chooses(pair.other_body)) {
    AddSidePairs(scene, pair, SideChoice::kFixed);
    return;
  }
  AddSidePairs(scene, pair, SideChoice::kHulls);
  AddSidePairs(scene, pair, SideChoice::kParts);
}

const geometry::ConvexShape& PartOrHull(const Body& body, int part) {
  ECPSIM_DEMAND(part < static_cast<int>(body.parts.size()));
  const auto& shape = part < 0 ? body.hull : body.parts[part];
  ECPSIM_DEMAND(shape != nullptr);
  return *shape;
}

}  // namespace

const geometry::ConvexShape& ShapeOfBody(const Scene& scene, const ContactPair& pair) {
  return PartOrHull(scene.bodies[pair.body], pair.part);
}

const geometry::ConvexShape& ShapeOfOther(const Scene& scene, const ContactPair& pair) {
  if (!pair.WithBody()) return *scene.obstacles[pair.obstacle].shape;
  return PartOrHull(scene.bodies[pair.other_body], pair.other_part);
}

ContactPair BodyPair(const Scene& scene, int i, int j, const Friction& friction) {
  const bool i_kinematic = scene.bodies[i].IsKinematic();
  ContactPair pair;
  pair.body = i_kinematic ? j : std::min(i, j);
  pair.other_body = i_kinematic ? i : std::max(i, j);
  pair.obstacle = -1;
  pair.friction = friction;
  return pair;
}

void AddBodyContacts(Scene& scene, int i, int j, const Friction& friction) {
  AddSides(scene, BodyPair(scene, i, j, friction));
}

void AddObstacleContacts(Scene& scene, int b, int o, const Friction& friction) {
  const ContactPair pair{b, o, friction};
  // a half-space reaches no cavity: the hull is exact against it
  if (scene.obstacles[o].shape && scene.obstacles[o].shape->IsHalfSpace()) {
    scene.contacts.push_back(pair);
    return;
  }
  AddSides(scene, pair);
}

void AddGripper(Scene& scene, Gripper gripper) {
  ECPSIM_DEMAND(gripper.motion != nullptr);
  const int index = static_cast<int>(scene.grippers.size());
  const KinematicPose frame = gripper.motion->PoseAt(0);
  for (int j = 0; j < 2; ++j) {
    const int b = gripper.jaws[j];
    ECPSIM_DEMAND(b >= 0 && b < static_cast<int>(scene.bodies.size()));
    Body& jaw = scene.bodies[b];
    gripper.jaw_in_frame[j].p = frame.q.conjugate() * (jaw.p0 - frame.p);
    gripper.jaw_in_frame[j].q = (frame.q.conjugate() * jaw.q0).normalized();
    if (jaw.gripper < 0) jaw.gripper = index;  // ValidateScene reports a body in two grippers
  }
  const double length = gripper.axis.norm();
  if (length > 0 && std::isfinite(length)) gripper.axis /= length;
  scene.grippers.push_back(std::move(gripper));
}

namespace {

// a motion given by expressions with compiled expressions of its own; the other forms have none
std::shared_ptr<const KinematicMotion> Recompiled(
    const std::shared_ptr<const KinematicMotion>& motion) {
  const auto* given = motion ? std::get_if<PoseExpressions>(&motion->form()) : nullptr;
  if (given == nullptr) return motion;
  PoseExpressions own = *given;
  for (TimeFunction& f : own.position) f = f.Recompiled();
  for (TimeFunction& f : own.rpy_deg) f = f.Recompiled();
  own.angle = own.angle.Recompiled();
  return std::make_shared<const KinematicMotion>(std::move(own), motion->where());
}

}  // namespace

void RecompileExpressions(Scene& scene) {
  for (Load& load : scene.loads) {
    load.x = load.x.Recompiled();
    load.y = load.y.Recompiled();
    load.z = load.z.Recompiled();
  }
  for (Body& body : scene.bodies) body.motion = Recompiled(body.motion);
  for (Gripper& gripper : scene.grippers) {
    gripper.motion = Recompiled(gripper.motion);
    gripper.force = gripper.force.Recompiled();
  }
}

KinematicPose JawOnFrame(const Gripper& gripper, int jaw, const KinematicPose& frame) {
  const KinematicPose& in_frame = gripper.jaw_in_frame[jaw];
  return {frame.p + frame.q.toRotationMatrix() * in_frame.p, frame.q * in_frame.q};
}

Eigen::Vector3d ClosingAxis(const Gripper& gripper, const KinematicPose& frame) {
  return (frame.q.toRotationMatrix() * gripper.axis).normalized();
}

}  // namespace ecpsim::engine
