#include "python/simulation.h"

#include <algorithm>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/models/hull_warm_start.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/scene_limits.h"
#include "engine/time_step.h"
#include "python/state_arrays.h"

namespace ecpsim::python {
namespace {

std::string Format(const Eigen::Vector3d& v) {
  return fmt::format("[{}, {}, {}]", v.x(), v.y(), v.z());
}

// a wrench's vector must be a number the engine's scales can square (scene_limits.h)
void RequireMagnitude(const Eigen::Vector3d& v, const std::string& what) {
  for (int i = 0; i < 3; ++i) {
    const std::string problem = engine::OutOfMagnitude(v[i]);
    if (!problem.empty()) {
      throw InputError(fmt::format("{} = {}: expected {}", what, Format(v), problem));
    }
  }
}

// a motion from `now` at t = k h to `target` at (k + 1) h, the times the step driver asks for
// (step_driver.cpp: PoseAt((steps + 1) h)); the last waypoint's pose holds after it
std::shared_ptr<const engine::KinematicMotion> StepTo(const engine::KinematicPose& now,
                                                      const engine::KinematicPose& target,
                                                      const engine::State& state, double h,
                                                      const std::string& where) {
  std::vector<engine::Waypoint> waypoints(2);
  waypoints[0].t = static_cast<double>(state.steps) * h;
  waypoints[0].pose = now;
  waypoints[1].t = static_cast<double>(state.steps + 1) * h;
  waypoints[1].pose = target;
  return std::make_shared<const engine::KinematicMotion>(std::move(waypoints), where);
}

// a hull warm start's multipliers are indexed by the sizes of its contact (hull_model.cpp):
// l by `window`, l_G by G's constraints (a fixed obstacle's all, a body's `other_window`), and
// `window` is searched as a sorted list. A state of another scene, or a pickle not made by
// get_state, must not reach the engine with other sizes. (The multi-patch model checks its own
// warm starts, FitsWarmStart, and the planar and point models keep none.)
void RequireFittingWarmStart(const engine::Scene& scene, size_t k, const engine::WarmStart& warm) {
  const auto* hull = warm.Get<engine::HullWarmStart>();
  if (hull == nullptr) return;
  const engine::ContactPair& pair = scene.contacts[k];
  const size_t g_count =
      pair.WithBody() ? hull->other_window.size()
                      : static_cast<size_t>(scene.obstacles[pair.obstacle].shape->NumConstraints());
  if (static_cast<size_t>(hull->l.size()) != hull->window.size() ||
      static_cast<size_t>(hull->l_g.size()) != g_count ||
      !std::is_sorted(hull->window.begin(), hull->window.end())) {
    const std::string& other =
        pair.WithBody() ? scene.bodies[pair.other_body].name : scene.obstacles[pair.obstacle].name;
    throw InputError(fmt::format(
        "set_state: contact {} ({}.{}): a hull warm start of {} multipliers for {} hull faces "
        "({}) and {} for G's constraints: expected as many as faces, sorted, and {} for G's (a "
        "state of another scene with as many bodies and contacts?)",
        k, scene.bodies[pair.body].name, other, hull->l.size(), hull->window.size(),
        std::is_sorted(hull->window.begin(), hull->window.end()) ? "sorted" : "not sorted",
        hull->l_g.size(), g_count));
  }
}

engine::Load ConstantLoad(engine::Load::Kind kind, int body, const Eigen::Vector3d& value) {
  engine::Load load;
  load.kind = kind;
  load.body = body;
  load.x = engine::TimeFunction(value.x());
  load.y = engine::TimeFunction(value.y());
  load.z = engine::TimeFunction(value.z());
  // active over every step while it is in the scene; Step removes it after one step
  load.start = 0;
  load.end = engine::kMaxMagnitude;
  return load;
}

}  // namespace

Simulation::Simulation(std::shared_ptr<const engine::Scene> scene)
    : original_(std::move(scene)), scene_(*original_), state_(engine::InitialState(scene_)) {
  // Simulations of one scene step on threads side by side (rollout): none waits for another's
  // evaluation of a shared expression
  engine::RecompileExpressions(scene_);
  report_.converged = true;
}

engine::StepReport Simulation::Step(std::int64_t n) {
  ECPSIM_DEMAND(n >= 1);
  if (!pending_.empty()) {
    // the wrenches are loads of this one step (engine::AppliedImpulse sums them into p_ext)
    const size_t base = scene_.loads.size();
    scene_.loads.insert(scene_.loads.end(), pending_.begin(), pending_.end());
    try {
      StepOnce();
    } catch (...) {
      scene_.loads.resize(base);
      throw;
    }
    scene_.loads.resize(base);
    pending_.clear();
    --n;
  }
  for (std::int64_t k = 0; k < n; ++k) StepOnce();
  return report_;
}

void Simulation::StepOnce() {
  try {
    report_ = engine::Step(scene_, state_, workspace_);
    failure_.clear();
  } catch (const engine::SolverFailure& e) {
    report_ = engine::StepReport();
    if (const engine::StepFailure* failure = e.step_failure()) {
      report_.residual = failure->residual;
      report_.retries = static_cast<int>(failure->tried.size());
    }
    failure_ = e.what();
    throw;
  } catch (const engine::ModelInvalid& e) {
    report_ = engine::StepReport();
    failure_ = e.what();
    throw;
  }
}

void Simulation::SetThreads(int threads) {
  engine::IslandThreadsOf(workspace_).SetThreads(threads);
}

void Simulation::Reset() {
  // everything the setters change in scene_: kinematic motions, masses, inertias (bodies),
  // friction (contacts), grippers' motions and forces
  scene_.bodies = original_->bodies;
  scene_.contacts = original_->contacts;
  scene_.grippers = original_->grippers;
  engine::RecompileExpressions(scene_);
  pending_.clear();
  state_ = engine::InitialState(scene_);
  report_ = engine::StepReport();
  report_.converged = true;
  failure_.clear();
}

void Simulation::SetState(const engine::State& state) {
  if (state.bodies.size() != scene_.bodies.size() ||
      state.contacts.size() != scene_.contacts.size()) {
    throw InputError(fmt::format(
        "set_state: a state of {} bodies and {} contacts: expected one of this scene ({}: {} "
        "bodies, {} contacts)",
        state.bodies.size(), state.contacts.size(), scene_.source, scene_.bodies.size(),
        scene_.contacts.size()));
  }
  for (size_t b = 0; b < state.bodies.size(); ++b) {
    if (!engine::IsFinite(state.bodies[b])) {
      throw InputError(fmt::format("set_state: body '{}': expected a finite pose and velocity",
                                   scene_.bodies[b].name));
    }
  }
  for (size_t k = 0; k < state.contacts.size(); ++k) {
    RequireFittingWarmStart(scene_, k, state.contacts[k].warm_start);
  }
  RequireApart(scene_, state, "set_state");
  state_ = state;
}

void Simulation::RequireBody(int body) const {
  ECPSIM_DEMAND(body >= 0 && static_cast<size_t>(body) < scene_.bodies.size());
}

void Simulation::ApplyWrench(int body, const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                             const std::optional<Eigen::Vector3d>& at_W) {
  RequireBody(body);
  const engine::Body& b = scene_.bodies[static_cast<size_t>(body)];
  const std::string where = fmt::format("apply_wrench(body '{}')", b.name);
  if (b.IsKinematic()) {
    throw InputError(
        fmt::format("{}: a kinematic body: expected a dynamic body (a kinematic one "
                    "follows its motion; set_kinematic_target moves it)",
                    where));
  }
  RequireMagnitude(force, where + ": force");
  RequireMagnitude(torque, where + ": torque");
  if (force.any()) {
    engine::Load load = ConstantLoad(engine::Load::Kind::kForce, body, force);
    if (at_W) {
      RequireMagnitude(*at_W, where + ": at");
      // the point rides with the body during the step, as a scene load's point does
      const engine::BodyState& s = state_.bodies[static_cast<size_t>(body)];
      load.at_point = true;
      load.point_B = s.Q_WB.conjugate() * (*at_W - s.p_WB);
    }
    pending_.push_back(std::move(load));
  }
  if (torque.any()) {
    pending_.push_back(ConstantLoad(engine::Load::Kind::kTorque, body, torque));
  }
}

void Simulation::SetMassProperties(int body, double mass, const Eigen::Matrix3d& inertia,
                                   const char* call) {
  RequireBody(body);
  engine::Body& b = scene_.bodies[static_cast<size_t>(body)];
  const std::string where = fmt::format("{}(body '{}')", call, b.name);
  if (b.IsKinematic()) {
    throw InputError(
        fmt::format("{}: a kinematic body: expected a dynamic body (a kinematic one "
                    "follows its motion; its mass is unused)",
                    where));
  }
  // the edit, checked as the loader checks a scene, undone when refused
  const double old_mass = b.mass;
  const Eigen::Matrix3d old_inertia = b.inertia;
  b.mass = mass;
  b.inertia = inertia;
  try {
    engine::ValidateMassProperties(scene_, body);
  } catch (const engine::SceneError& e) {
    b.mass = old_mass;
    b.inertia = old_inertia;
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
}

void Simulation::SetMass(int body, double mass, const std::optional<Eigen::Matrix3d>& inertia) {
  RequireBody(body);
  const engine::Body& b = scene_.bodies[static_cast<size_t>(body)];
  // a uniform density: the inertia scales with the mass (a NaN or negative mass is refused
  // before the inertia is looked at)
  SetMassProperties(body, mass, inertia ? *inertia : Eigen::Matrix3d(b.inertia * (mass / b.mass)),
                    "set_mass");
}

void Simulation::SetInertia(int body, const Eigen::Matrix3d& inertia) {
  RequireBody(body);
  SetMassProperties(body, scene_.bodies[static_cast<size_t>(body)].mass, inertia, "set_inertia");
}

void Simulation::SetFriction(int contact, const FrictionChange& change) {
  ECPSIM_DEMAND(contact >= 0 && static_cast<size_t>(contact) < scene_.contacts.size());
  engine::ContactPair& pair = scene_.contacts[static_cast<size_t>(contact)];
  const engine::Friction old = pair.friction;
  if (change.mu) pair.friction.mu = *change.mu;
  if (change.e_t) pair.friction.e_t = *change.e_t;
  if (change.e_o) pair.friction.e_o = *change.e_o;
  if (change.e_r) {
    pair.friction.e_r = *change.e_r;
    pair.friction.e_r_patch = false;
  }
  if (change.e_r_patch) pair.friction.e_r_patch = true;
  try {
    engine::ValidateContactFriction(scene_, contact);
  } catch (const engine::SceneError& e) {
    pair.friction = old;
    // the contact's own key (contacts[k].friction.*), the last of those the loader names
    throw InputError(fmt::format("set_friction(contact '{}'): {} = {}: expected {}",
                                 ContactName(scene_, pair), e.keys().back(), e.value(),
                                 e.expected()));
  }
}

void Simulation::SetKinematicTarget(int body, const engine::KinematicPose& target) {
  RequireBody(body);
  engine::Body& b = scene_.bodies[static_cast<size_t>(body)];
  const std::string where = fmt::format("set_kinematic_target(body '{}')", b.name);
  if (!b.IsKinematic()) {
    throw InputError(
        fmt::format("{}: a dynamic body: expected a kinematic one (`kinematic: "
                    "true`); apply_wrench pushes a dynamic body",
                    where));
  }
  const engine::BodyState& s = state_.bodies[static_cast<size_t>(body)];
  b.motion = StepTo({s.p_WB, s.Q_WB}, target, state_, scene_.h, where);
}

void Simulation::SetGripperTarget(int gripper, const engine::KinematicPose& frame,
                                  std::optional<double> force) {
  ECPSIM_DEMAND(gripper >= 0 && static_cast<size_t>(gripper) < scene_.grippers.size());
  engine::Gripper& g = scene_.grippers[static_cast<size_t>(gripper)];
  const std::string where = fmt::format("set_gripper_target(gripper '{}')", g.name);
  if (force && !(*force >= 0 && *force <= engine::kMaxMagnitude)) {
    throw InputError(fmt::format("{}: force = {}: expected a closing force ≥ 0 N within {:g}",
                                 where, *force, engine::kMaxMagnitude));
  }
  const engine::KinematicPose now = g.motion->PoseAt(static_cast<double>(state_.steps) * scene_.h);
  g.motion = StepTo(now, frame, state_, scene_.h, where);
  if (force) g.force = engine::TimeFunction(*force);
}

}  // namespace ecpsim::python
