#pragma once
// The state machine behind the Python module's `Simulation`: a scene, its state, and the inputs a
// controller gives between steps (external wrenches for the next step, kinematic and gripper
// targets). Plain
// C++, no Python: the bindings (python/ecpsim_module.cpp) only convert.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/cancel_flag.h"
#include "engine/island_threads.h"
#include "engine/kinematic_motion.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"
#include "engine/time_step.h"

namespace ecpsim::python {

/// One simulation of a scene, stepped on request. Not thread-safe: one thread at a time per
/// object (separate objects, even of the same scene, may step in parallel).
class Simulation {
 public:
  /// Starts at engine::InitialState of `scene` (which must have passed ValidateScene).
  explicit Simulation(std::shared_ptr<const engine::Scene> scene);

  /// Takes `n` ≥ 1 steps of scene.h; the wrenches given by ApplyWrench since the last step act on
  /// the first of them only. Returns the last step's report.
  /// @throws engine::SolverFailure, engine::ModelInvalid, InputError as engine::Step; the state
  ///         is then the one after the last step that succeeded, and wrenches not yet applied
  ///         stay pending.
  engine::StepReport Step(std::int64_t n);

  /// Steps stop at their next solver iteration, undone, throwing Cancelled, once `flag` is raised
  /// (null: never; engine::StopStepsOn).
  void StopOn(const CancelFlag* flag) { engine::StopStepsOn(workspace_, flag); }

  /// Solve each step's islands on `threads` threads (engine/island_threads.h; 1 at first): the
  /// result is the same, bit for bit, for any number.
  /// @throws InputError for threads < 1.
  void SetThreads(int threads);
  int threads() { return engine::IslandThreadsOf(workspace_).threads(); }

  /// Back to the initial state; pending wrenches dropped, kinematic targets undone, and the
  /// masses, inertias and friction of SetMass, SetInertia and SetFriction restored to the scene's.
  void Reset();

  /// Replaces the state (e.g. one saved by state()); stepping on from it is bit-identical to
  /// stepping on from where it was saved, given the same inputs.
  /// @throws InputError if its body or contact count does not fit the scene, a body's pose or
  ///         velocity is not finite, or a contact's hull warm start does not have the sizes of
  ///         that contact (a state of another scene).
  void SetState(const engine::State& state);

  /// Adds a wrench on dynamic body `body` for the next step: `force` (N, world) at the world point
  /// `at_W` (the body's CM when absent) and `torque` (N·m, world). It enters the step's MNCP as an
  /// applied impulse exactly like a scene load (engine/loads.h): force · h, torque · h, with the
  /// point fixed in the body.
  /// @throws InputError for a kinematic or unknown body or a value not finite within ±1e150.
  void ApplyWrench(int body, const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                   const std::optional<Eigen::Vector3d>& at_W);

  /// Prescribes kinematic body `body`'s pose at the end of the next step (p in m, world; q unit,
  /// body → world); it moves there at a constant twist over the step and stays until the next
  /// target (or Reset, which restores the scene's motion).
  /// @throws InputError for a dynamic or unknown body, a non-finite or zero quaternion, or a turn
  ///         of π or more within the step.
  void SetKinematicTarget(int body, const engine::KinematicPose& target);

  /// Prescribes gripper `gripper`'s frame pose at the end of the next step (as SetKinematicTarget
  /// a kinematic body's: a constant twist over the step, held until the next target) and, when
  /// given, its closing force (N on each jaw) from the next step on.
  /// @throws InputError for an unknown gripper, a force that is negative or not finite within
  ///         ±1e150, a non-finite or zero quaternion, or a turn of π or more within the step.
  void SetGripperTarget(int gripper, const engine::KinematicPose& frame,
                        std::optional<double> force);

  /// Sets dynamic body `body`'s mass (kg) from the next step on, in this simulation's copy of the
  /// scene (the scene given stays as it was; Reset restores its value). Its inertia becomes
  /// `inertia` (kg·m², about the CM in body axes) when given, else the present one scaled by the
  /// ratio of the masses (a uniform density: the loader's m · unit inertia, to the last bit when
  /// the ratio is a power of two).
  /// @throws InputError for a kinematic body, or a mass or inertia that ValidateScene refuses
  ///         (engine::ValidateMassProperties: its message, prefixed "set_mass(body '...')");
  ///         nothing changes then.
  void SetMass(int body, double mass, const std::optional<Eigen::Matrix3d>& inertia);

  /// Sets dynamic body `body`'s inertia (kg·m², about the CM in body axes), as SetMass.
  /// @throws InputError for a kinematic body or an inertia that ValidateScene refuses (not
  ///         symmetric positive definite, the triangle inequality, a moment or radius of gyration
  ///         out of range); nothing changes then.
  void SetInertia(int body, const Eigen::Matrix3d& inertia);

  /// New values of a contact's friction; the ones left empty keep theirs.
  struct FrictionChange {
    std::optional<double> mu, e_t, e_o;
    std::optional<double> e_r;  // m; a number replaces `e_r: patch`
    bool e_r_patch = false;     // `e_r: patch` (docs/scene_format.md) instead of a number
  };

  /// Changes contact `contact`'s friction (scene.contacts order) from the next step on, in this
  /// simulation's copy of the scene, as SetMass.
  /// @throws InputError for a value that ValidateScene refuses (engine::ValidateContactFriction:
  ///         μ ≥ 0, e_t, e_o > 0, e_r a length > 0, each finite); nothing changes then.
  void SetFriction(int contact, const FrictionChange& change);

  /// The scene as stepped: the scene given, with the kinematic targets, masses, inertias and
  /// friction set so far.
  const engine::Scene& scene() const { return scene_; }
  const engine::State& state() const { return state_; }
  /// The state for direct edits of poses and velocities (callers keep it finite).
  engine::State& mutable_state() { return state_; }
  /// The report of the last step (iterations 0, converged before any step); of a step that
  /// failed: converged false, its residual and the number of starts it tried.
  const engine::StepReport& last_report() const { return report_; }
  /// The message of the last step's failure; empty when it succeeded.
  const std::string& last_failure() const { return failure_; }
  /// The wrenches given by ApplyWrench for the next step, as the loads it adds to the scene.
  const std::vector<engine::Load>& pending_wrenches() const { return pending_; }

 private:
  void RequireBody(int body) const;
  // one engine::Step, its report or failure recorded
  void StepOnce();

  // dynamic body `body`'s mass and inertia, kept if ValidateMassProperties accepts them
  void SetMassProperties(int body, double mass, const Eigen::Matrix3d& inertia, const char* call);

  std::shared_ptr<const engine::Scene> original_;
  // *original_ plus kinematic targets, masses, inertias and friction; the next step's wrenches as
  // loads
  engine::Scene scene_;
  engine::State state_;
  std::vector<engine::Load> pending_;  // the next step's wrenches
  engine::StepReport report_;
  std::string failure_;
  engine::StepWorkspace workspace_;  // the steps' memory, kept from step to step
};

}  // namespace ecpsim::python
