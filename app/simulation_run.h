#pragma once
// The loop shared by `ecpsim run` and `ecpsim drop`: step a scene to its duration, writing
// DIR/trajectory.csv and DIR/summary.json.

#include <array>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/checkpoint.h"
#include "engine/scene_io/loaded_scene.h"
#include "engine/state.h"

namespace ecpsim::app {

/// What summary.json holds (see RunSimulation).
struct RunSummary {
  long steps = 0;              // steps completed
  double t_end = 0;            // s, the time of the last state
  long rows = 0;               // rows of trajectory.csv below its header
  long planned_steps = 0;      // ceil(duration / h)
  int failures = 0;            // 0, or 1 when a SolverFailure stopped the run
  long retries = 0;            // Σ StepReport::retries
  double iterations_mean = 0;  // Newton iterations per step
  int iterations_max = 0;
  double residual_max = 0;  // largest unscaled residual of any step
  int substeps_max = 1;
  double max_penetration = 0;   // m, deepest mesh vertex inside an obstacle at t = 0 or after
                                // any step
  double wall_s = 0;            // s, the whole loop including output
  double median_step_us = 0;    // µs, median of engine::Step's wall time (ReservoirMedian: exact
                                // up to 16384 steps, its rank within ±1.2 % beyond)
  bool converged = false;       // every step converged and the run reached the duration
  int interrupt_signal = 0;     // SIGINT or SIGTERM when a signal stopped the run, else 0
  long resumed_from_step = -1;  // the step a resumed run continued from, else -1
  std::string error;            // the failure's message, empty on success
  // body-steps solved by each engine::StepModel (indexed by it): summary.json's "models"
  std::array<long, engine::kNumStepModels> model_steps{};
  // body-steps that replayed their island's last step (engine/README.md, "Sleeping islands"):
  // summary.json's "sleeping_body_steps"
  long sleeping_body_steps = 0;
};

/// How RunSimulation runs, besides the scene and the folder.
using StepObserver =
    std::function<void(const engine::State& state, const engine::StepReport& report)>;
struct RunSetup {
  bool progress = false;  // a progress bar on stderr (callers pass isatty(stderr))
  /// If set, sees the initial state and the state after every step (e.g. to record frames);
  /// an exception from it stops the run like a solver failure.
  StepObserver observer;
  /// How the run was started (Checkpoint::origin), kept in checkpoint.json for a resume.
  nlohmann::json origin;
  /// If set, the run continues from this checkpoint (written by an earlier RunSimulation into
  /// the same folder with the same scene) instead of starting at t = 0: trajectory.csv keeps its
  /// first `resume->rows` rows and grows from there, the totals go on, the observer sees only
  /// the new states. The result is the same, bit for bit, as a run that never stopped.
  const Checkpoint* resume = nullptr;
  /// A run that reaches the end leaves a resumed run's checkpoint.json in place, for the caller
  /// to remove (RemoveCheckpoint) once its own outputs are finished: frames and video are joined
  /// after the steps, and a run killed meanwhile must stay resumable.
  bool keep_checkpoint = false;
  /// Threads that solve a step's islands (engine/island_threads.h): the result is the same for
  /// any number.
  int threads = 1;
};

/// Removes DIR/checkpoint.json if there is one (nothing is left to resume).
void RemoveCheckpoint(const std::string& out_dir);

/// Steps `loaded.scene` from engine::InitialState until its duration (ceil(duration / h) steps of
/// h) and writes, in `out_dir` (created if missing); memory does not grow with the number of steps:
/// - trajectory.csv: the initial state, every `loaded.output.every`-th step and the last step
///   (columns: TrajectoryColumns), streamed to a temporary file and renamed at the end, also
///   when the run fails, so the rows written stay valid;
/// - summary.json (atomically): RunSummary's fields plus `scene`, `h`, `duration`, `t_end`, `rows`,
///   `interrupted`, and `resumed_from_step` for a resumed run.
/// Both replace only regular files (common/atomic_file.h).
/// A run that stops early (interrupt, or an exception from engine::Step) also writes
/// checkpoint.json (app/checkpoint.h): the exact state after its last step, for a resume; a run
/// that reaches the end removes the folder's checkpoint.json (unless setup.keep_checkpoint).
/// Under an InterruptGuard (app/interrupt.h), a SIGINT or SIGTERM stops the run within the step
/// in progress, which is left undone (within one solver iteration: a step of minutes does not
/// hold the signal up): the trajectory then ends with the row of the last step done (whatever
/// output.every says, as after a solver failure), summary.json has `"interrupted": true`,
/// `"signal"` and the steps done, and the summary returned names the signal (interrupt_signal);
/// no exception.
/// @throws engine::SolverFailure (after writing the files) when a step cannot be solved or
///         the state stops being finite; InputError, before any step, if `out_dir` cannot be
///         written, something other than a regular file is at one of the paths, the run would
///         take more than 2^53 steps, or the checkpoint to resume does not fit the folder's
///         trajectory.csv.
RunSummary RunSimulation(const engine::LoadedScene& loaded, const std::string& out_dir,
                         const RunSetup& setup);

}  // namespace ecpsim::app
