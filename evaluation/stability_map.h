#pragma once
// Stability maps: each method run over step size × a scenario parameter (impact speed, plate
// aspect ratio, T-bar mass ratio, push speed), each run classified ok or by how it failed.

#include <functional>
#include <string>
#include <vector>

#include "evaluation/method.h"
#include "evaluation/scenario.h"
#include "evaluation/trajectory_run.h"

namespace ecpsim::evaluation {

/// How a run ended; Classify checks energy gain first (the cause when a growing spin ends in
/// a failure), then failure, penetration, mode and rest.
enum class Outcome {
  kOk = 0,
  kSolverFailure,  // the method threw (solver failure, invalid model) or its state blew up
  kPenetration,    // a mesh vertex got deeper than kPenetrationLimit into the ground
  kEnergyGain,     // energy rose above its start by more than kEnergyGainFraction of the KE
  kWrongMode,      // not resting on a face at the end (the reference's final mode)
  kJitter,         // still moving or drifting over the last 0.5 s, when it should rest
  kOffSpeed,       // a pushed body not at the pusher's velocity over the last 0.5 s
};
constexpr int kOutcomeCount = 7;
const char* OutcomeName(Outcome outcome);  // ok, solver_failure, penetration, energy_gain, …

constexpr double kPenetrationLimit = 1e-3;    // m, the "penetration > 1 mm"
constexpr double kEnergyGainFraction = 0.01;  // of the initial kinetic energy, + 1e-6 J
constexpr double kJitterSpeed = 1e-2;         // m/s, |v| + length·|ω| in the last 0.5 s
constexpr double kJitterDrift = 1e-3;         // m, |Δp| + length·|Δθ| in the last 0.5 s
// relative to the pusher's speed: how far a pushed body's velocity may be from the pusher's at
// the samples of the last 0.5 s. A steady push through the CM carries the box at the pusher's
// speed exactly; 5 % is far above a converged solver's error and catches a contact that breaks
// (the box left behind, or knocked ahead) or chatters (soft contacts' spring-back)
constexpr double kPushSpeedTolerance = 0.05;

/// One map: a family of scenarios over `values` of a parameter; by default each must end resting
/// on a face (Classify), else as `classify` says.
struct StabilityMapSpec {
  std::string name;  // impact, thin_plate, tbar_mass_ratio, push_speed
  std::string description;
  std::string value_label;  // the parameter with its unit, for the chart's y axis
  std::vector<double> values;
  std::function<Scenario(double value)> scenario;
  // the run's outcome; empty: Classify with the measured body's initial kinetic energy
  std::function<Outcome(const RunRecord& run, const Scenario& scenario)> classify;
};

/// The four maps of docs/benchmarks.md; push_speed reads push_box.yaml from `scenes_dir` when
/// its scenarios are made (InputError if it is missing or invalid).
std::vector<StabilityMapSpec> StabilityMaps(const std::string& scenes_dir);

/// Classifies a run of a scenario that starts with kinetic energy `initial_kinetic` (J).
Outcome Classify(const RunRecord& run, double initial_kinetic);

/// Classifies a push at the constant velocity `pusher_velocity` (m/s, world): failure, then
/// penetration (of the ground or between the bodies) beyond kPenetrationLimit, then a sample of
/// the last `late_window` seconds whose velocity differs from the pusher's by more than
/// kPushSpeedTolerance of its speed (kOffSpeed); else ok. Energy is not checked: the pusher
/// does work.
Outcome ClassifyPush(const RunRecord& run, const Scenario& scenario,
                     const Eigen::Vector3d& pusher_velocity, double late_window);

struct StabilityRow {
  std::string map;
  std::string method;
  double h = 0;
  double value = 0;
  Outcome outcome = Outcome::kOk;
  double max_penetration = 0;  // m
  double energy_gain = 0;      // J, max over samples of E − E(0)
  double max_speed_late = 0;   // m/s
  double drift_late = 0;       // m
  std::string final_mode;      // ContactModeName at the end
  std::string failure;
};

/// Runs this shard's part of the maps: cells cut into (map, method) groups in order, group g
/// (0-based) belongs to shard (g mod shard_count) + 1. `progress` gets a line per group.
std::vector<StabilityRow> RunStabilityMaps(const std::vector<StabilityMapSpec>& maps,
                                           const std::vector<Method>& methods,
                                           const std::vector<double>& steps, int shard_index,
                                           int shard_count, double cpu_limit_s,
                                           const std::function<void(const std::string&)>& progress);

std::string StabilityCsv(const std::vector<StabilityRow>& rows);
/// @throws InputError naming file, line and column for a malformed file.
std::vector<StabilityRow> ReadStabilityCsv(const std::string& path);

}  // namespace ecpsim::evaluation
