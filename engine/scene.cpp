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
