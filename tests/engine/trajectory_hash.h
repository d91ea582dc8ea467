#pragma once
// Pins every shipped scene's trajectory bit for bit: a hash of the state after each step of a
// short run of scenes/*.yaml under each contact model, against the table
// tests/engine/trajectory_hashes.txt (re-blessed by scripts/bless_trajectory_hashes.sh).

#include <cstdint>
#include <string>
#include <vector>

#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine::testing {

/// One scene file under one contact model.
struct TrajectoryCase {
  std::string scene;  // file name in scenes/, e.g. "desk.yaml"
  std::string model;  // "auto", "hull", "planar", "multipatch" or "point"
};

/// Every scenes/*.yaml (sorted by name) under every contact model, the scene's own first.
std::vector<TrajectoryCase> AllTrajectoryCases(const std::string& scenes_dir);

/// The table's lines of one case: "<scene> <model> <step> <16 hex digits>" for each step, the
/// hash of the bits of the time, every body's pose and velocities, every contact's solution and
/// the step's report; then "<scene> <model> end <outcome>" where the outcome is "completed",
/// "ModelInvalid at step N" (the model does not apply) or "SolverFailure at step N".
/// @throws InputError where the scene does not load.
std::vector<std::string> TrajectoryRecord(const std::string& scenes_dir,
                                          const TrajectoryCase& trajectory_case);

/// FNV-1a of the bits of the state's time, bodies and contact solutions and of the step's report.
std::uint64_t HashStep(const State& state, const StepReport& report);

/// The steps a case runs: short enough that every case stays cheap, long enough to pass the
/// scenes' first landings and mode changes.
int TrajectoryHashSteps(const std::string& scene);

}  // namespace ecpsim::engine::testing
