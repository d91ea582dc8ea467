#pragma once
// The work–precision sweep: every method on every scenario at every step size, its errors
// against the scenario's reference and its CPU time per simulated second; as CSV rows that
// shards of the sweep write and a merge joins.

#include <functional>
#include <string>
#include <vector>

#include "evaluation/method.h"
#include "evaluation/scenario.h"
#include "evaluation/trajectory_run.h"

namespace ecpsim::evaluation {

/// One run of the sweep. Errors that were not measured are −1 (never NaN).
struct WorkPrecisionRow {
  std::string scenario;
  std::string method;
  double h = 0;    // s
  long steps = 0;  // steps completed
  bool failed = false;
  // CPU seconds per simulated second (thread CPU time of Step()); −1 where the run failed or
  // simulated no time
  double cpu_per_sim_s = -1;
  double error_state = -1;      // m, vs the scenario's reference (TrajectoryErrors::state)
  double error_position = -1;   // m
  double error_angle = -1;      // rad
  double error_velocity = -1;   // m/s
  double wrong_mode = -1;       // fraction of samples in the wrong contact mode
  double stop_time_error = -1;  // s
  double error_vs_hull = -1;    // m, state error vs the hull model's converged solution
  double reference_uncertainty = -1;  // m, converged reference at h_ref vs 2 h_ref (0: analytic)
  double max_penetration = 0;         // m
  double iterations_mean = 0;         // per step (Newton iterations or Lemke pivots; 0 external)
  int iterations_max = 0;
  // a push (Scenario::pusher): the pusher's force after it settled (RunRecord::push_forces)
  // against the closed form's steady force F: max |f − F| / F over the steps, and the fraction
  // of steps in which the contact broke (f ≤ 0); −1 where there is no push or the run failed
  double push_force_error = -1;
  double push_contact_breaks = -1;
  // m, drift (Scenario::measure_drift): the largest projected CM displacement of any dynamic
  // body from its start (RunRecord::max_drift); −1 where not measured or the run failed
  double drift = -1;
  std::string failure;  // message of the failure (commas and newlines replaced)
};

struct SweepOptions {
  std::vector<double> steps = {0.02, 0.01, 0.005, 0.002, 0.001, 0.0005, 0.0002};  // s
  // a converged reference runs the same method at min(steps) / reference_divisor and is
  // checked against a run at twice that step (WorkPrecisionRow::reference_uncertainty)
  double reference_divisor = 16;
  double cpu_limit_s = 300;  // per run
  int shard_index = 1;       // this process runs shard shard_index of shard_count (1-based)
  int shard_count = 1;
  std::function<void(const std::string& message)> progress;  // one line per finished group
};

/// s: a run's CPU time below this is timed again. A single run of a few milliseconds reads high
/// (its first steps fill the caches) and scatters: on the shared 2-core machine the stack's 50
/// steps at h = 0.02 s took 0.51 … 0.60 ms as single runs in six sweeps, 0.29 … 0.47 ms as the
/// median of this rule's runs; auto's cost over hull's there, where both take the hull model's
/// steps, read 0.62 … 0.87 from single runs and 0.94 … 1.03 from the medians
inline constexpr double kMinTimedCpuSeconds = 0.05;
/// runs timed at most (a run of 0.5 ms is timed 25 times, 12.5 ms in all)
inline constexpr int kMaxTimedRuns = 25;

struct TimedCpu {
  double cpu_seconds = 0;  // the median of the runs' CPU times
  int runs = 0;            // runs timed, `first` included
};

/// The CPU time of `first`, a completed run of `method` on `scenario` at step h: where it took
/// less than kMinTimedCpuSeconds, the median of it and further runs of the same (deterministic)
/// trajectory until their times add up to that, at most kMaxTimedRuns runs in all.
TimedCpu TimedCpuSeconds(const Method& method, const Scenario& scenario, double h,
                         const RunRecord& first, double cpu_limit_s);

/// Whether `method` applies to `scenario` (planar: flat throughout; multipatch: half-spaces).
bool MethodApplies(const Method& method, const Scenario& scenario);

/// Runs this shard's part of the sweep. The work is cut into (scenario, method) groups in the
/// order given; group g (0-based) belongs to shard (g mod shard_count) + 1. A group runs all
/// step sizes, after computing the references it needs.
std::vector<WorkPrecisionRow> RunWorkPrecision(const std::vector<Scenario>& scenarios,
                                               const std::vector<Method>& methods,
                                               const SweepOptions& options);

/// The CSV text (header + one line per row).
std::string WorkPrecisionCsv(const std::vector<WorkPrecisionRow>& rows);

/// Parses a file written by WorkPrecisionCsv, or by its earlier writer without the `drift`
/// column (drift −1).
/// @throws InputError naming the file, line and column for anything else.
std::vector<WorkPrecisionRow> ReadWorkPrecisionCsv(const std::string& path);

}  // namespace ecpsim::evaluation
