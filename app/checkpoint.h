#pragma once
// DIR/checkpoint.json: where a run that stopped early stood, exactly, so that `ecpsim run --resume
// DIR` continues it bit for bit. This file and checkpoint.cpp are the only ones that know the
// format; the engine's State in it is a state record (engine/report/state_record.h), as in a
// Python pickle, every double a hexadecimal float, which reads back to the same bits.

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "common/reservoir_median.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::app {

/// The sums and maxima behind summary.json over the steps done so far.
struct RunTotals {
  long steps = 0;       // steps done
  long retries = 0;     // Σ StepReport::retries
  long iterations = 0;  // Σ Newton iterations
  int iterations_max = 0;
  double residual_max = 0;  // largest unscaled residual of any step
  int substeps_max = 1;
  double max_penetration = 0;  // m, deepest mesh vertex inside an obstacle, t = 0 included
  bool all_converged = true;   // every step converged
  double wall_s = 0;           // s, wall time of the run's earlier parts (before a resume)
  ReservoirMedian step_us;     // µs, wall time of engine::Step
  // body-steps solved by each engine::StepModel (indexed by it)
  std::array<long, engine::kNumStepModels> model_steps{};
  long sleeping_body_steps = 0;  // Σ StepReport::sleeping_bodies
};

struct Checkpoint {
  /// How the run was started: command, arguments, a fingerprint of its inputs and the ecpsim
  /// version (built and compared by the `run` command; stored as given).
  nlohmann::json origin;
  /// Rows of trajectory.csv (below the header) that an uninterrupted run also writes up to
  /// `state`; a resumed run keeps these and drops the row written for the stop itself.
  long rows = 0;
  RunTotals totals;
  engine::State state;  // after totals.steps steps
};

/// Writes `checkpoint` to `path` atomically (common/atomic_file.h).
/// @throws InputError if it cannot be written.
void WriteCheckpoint(const std::string& path, const Checkpoint& checkpoint);

/// Reads a checkpoint written by WriteCheckpoint. Its state is checked against nothing but the
/// format: compare `origin` first, then call CheckFitsScene.
/// @throws InputError naming the file and, for a malformed one, the key and what was expected; a
///         missing file is "no checkpoint there: nothing to resume".
Checkpoint ReadCheckpoint(const std::string& path);

/// @throws InputError naming `path` if the state's bodies and contacts are not those of `scene`.
void CheckFitsScene(const Checkpoint& checkpoint, const engine::Scene& scene,
                    const std::string& path);

}  // namespace ecpsim::app
