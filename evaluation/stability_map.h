#pragma once
// Stability maps: each method run over step size × a scenario parameter (impact speed, plate
// aspect ratio, T-bar mass ratio), each run classified ok or by how it failed.

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
  kSolverFailure,   // the method threw (solver failure, invalid model) or its state blew up
  kPenetration,     // a mesh vertex got deeper than kPenetrationLimit into the ground
  kEnergyGain,      // energy rose above its start by more than kEnergyGainFraction of the KE
  kWrongMode,       // not resting on a face at the end (the reference's final mode)
  kJitter,          // still moving or drifting over the last 0.5 s, when it should rest
};
constexpr int kOutcomeCount = 6;
const char* OutcomeName(Outcome outcome);  // ok, solver_failure, penetration, energy_gain, …

constexpr double kPenetrationLimit = 1e-3;     // m, the "penetration > 1 mm"
constexpr double kEnergyGainFraction = 0.01;   // of the initial kinetic energy, + 1e-6 J
constexpr double kJitterSpeed = 1e-2;          // m/s, |v| + length·|ω| in the last 0.5 s
constexpr double kJitterDrift = 1e-3;          // m, |Δp| + length·|Δθ| in the last 0.5 s

/// One map: a family of scenarios over `values` of a parameter; each must end resting on a face.
struct StabilityMapSpec {
  std::string name;         // impact, thin_plate, tbar_mass_ratio
  std::string description;
  std::string value_label;  // the parameter with its unit, for the chart's y axis
  std::vector<double> values;
  std::function<Scenario(double value)> scenario;
};

/// The three maps of docs/benchmarks.md.
std::vector<StabilityMapSpec> StabilityMaps();

/// Classifies a run of a scenario that starts with kinetic energy `initial_kinetic` (J).
Outcome Classify(const RunRecord& run, double initial_kinetic);

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
