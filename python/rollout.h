#pragma once
// Batched rollouts: many Simulations stepped a number of steps each on a few threads, their poses
// and velocities written after every step (the Python module's `ecpsim.rollout`). Plain C++, no
// Python: python/rollout_bindings.cpp converts.

#include <cstdint>
#include <exception>
#include <mutex>
#include <string>
#include <vector>

#include "common/cancel_flag.h"
#include "engine/scene.h"
#include "python/simulation.h"

namespace ecpsim::python {

/// Where one simulation's rows go, each `steps` rows of n bodies, row-major: positions,
/// velocities and angular velocities (steps, n, 3) in m, m/s, rad/s (world), quaternions
/// (steps, n, 4) as (w, x, y, z), time (steps) in s and converged (steps), row k after the
/// simulation's (k + 1)-th step of the rollout.
struct RolloutRows {
  double* positions = nullptr;
  double* quaternions = nullptr;
  double* velocities = nullptr;
  double* angular_velocities = nullptr;
  double* time = nullptr;
  bool* converged = nullptr;
};

/// One simulation of a rollout.
struct RolloutJob {
  Simulation* sim = nullptr;
  std::mutex* mutex = nullptr;  // held while the simulation steps (one thread at a time in it)
  // the scene the simulation was made of (immutable): which bodies are kinematic, their names
  const engine::Scene* scene = nullptr;
  // (steps, n, 6) row-major: per step and body, force (N, world, at the CM) then torque (N·m,
  // world), applied on that step as Simulation::ApplyWrench; null for none
  const double* controls = nullptr;
  RolloutRows rows;
};

/// A simulation of a rollout that stopped: its step `steps_done + 1` raised `error` (with
/// message `message`); it holds the state after its `steps_done` good steps, at time `t` s, and
/// the wrenches of the failed step stay pending (as Simulation::Step leaves them).
struct RolloutFailure {
  size_t simulation = 0;  // index into the jobs
  std::int64_t steps_done = 0;
  double t = 0;
  std::string message;
  std::exception_ptr error;
};

/// How far a rollout took one job: its steps done, whether the controls of the next one are
/// applied already (a step stopped by the cancel flag leaves them pending, as a failed one does),
/// and whether it is over (all its steps taken, or failed).
struct RolloutProgress {
  std::int64_t steps_done = 0;
  bool controls_pending = false;
  bool over = false;
};

/// Checks `job`'s controls before any step (`index`: the job's place, for the message): every
/// value finite within ±kMaxMagnitude, and a kinematic body's rows zero (its motion is
/// prescribed; no wrench moves it).
/// @throws InputError naming the simulation, step, body and value.
void CheckControls(const RolloutJob& job, size_t index, std::int64_t steps);

/// Steps each job's simulation `steps` ≥ 1 times on `threads` ≥ 1 threads (the calling one and
/// threads − 1 more; each takes the next job not yet taken, locks its mutex and steps it to the
/// end), applying its controls before each step and writing its rows after it. The jobs are
/// independent, so every row is the same double whatever `threads` is. A job whose step fails
/// (SolverFailure, ModelInvalid, InputError of a load) stops there, the others go on. Once
/// `cancel` (may be null) is raised, every job's step in progress stops within a solver
/// iteration, undone (Simulation::StopOn), and no job starts: `progress` (one per job, kept by
/// the caller) says where each stands, and a later call with it takes each job on from there.
/// Preconditions: distinct simulations, controls checked by CheckControls, rows of room for
/// `steps` rows of the simulation's bodies, `progress` sized as `jobs`.
/// @returns the jobs that failed in this call, by index.
std::vector<RolloutFailure> Rollout(const std::vector<RolloutJob>& jobs, std::int64_t steps,
                                    int threads, const CancelFlag* cancel,
                                    std::vector<RolloutProgress>& progress);

}  // namespace ecpsim::python
