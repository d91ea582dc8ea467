#include "evaluation/work_precision.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/errors.h"
#include "evaluation/csv_file.h"
#include "evaluation/error_metrics.h"
#include "evaluation/median.h"
#include "evaluation/trajectory_run.h"

namespace ecpsim::evaluation {
namespace {

// work_precision.csv's columns, in order
using Row = WorkPrecisionRow;
constexpr int kDigits = 9;  // significant digits of every number: errors and times, not a state
const std::vector<CsvColumn<Row>> kColumns = {
    TextColumn<Row>("scenario", &Row::scenario),
    TextColumn<Row>("method", &Row::method),
    NumberColumn<Row>("h", kDigits, &Row::h),
    WholeColumn<Row>("steps", &Row::steps),
    FlagColumn<Row>("failed", &Row::failed),
    NumberColumn<Row>("cpu_per_sim_s", kDigits, &Row::cpu_per_sim_s),
    NumberColumn<Row>("error_state", kDigits, &Row::error_state),
    NumberColumn<Row>("error_position", kDigits, &Row::error_position),
    NumberColumn<Row>("error_angle", kDigits, &Row::error_angle),
    NumberColumn<Row>("error_velocity", kDigits, &Row::error_velocity),
    NumberColumn<Row>("wrong_mode", kDigits, &Row::wrong_mode),
    NumberColumn<Row>("stop_time_error", kDigits, &Row::stop_time_error),
    NumberColumn<Row>("error_vs_hull", kDigits, &Row::error_vs_hull),
    NumberColumn<Row>("reference_uncertainty", kDigits, &Row::reference_uncertainty),
    NumberColumn<Row>("max_penetration", kDigits, &Row::max_penetration),
    NumberColumn<Row>("iterations_mean", kDigits, &Row::iterations_mean),
    WholeColumn<Row>("iterations_max", &Row::iterations_max),
    NumberColumn<Row>("push_force_error", kDigits, &Row::push_force_error),
    NumberColumn<Row>("push_contact_breaks", kDigits, &Row::push_contact_breaks),
    NumberColumn<Row>("drift", kDigits, &Row::drift),
    TextColumn<Row>("failure", &Row::failure),
};

// the columns before `drift` was added: shards of that build still merge
std::vector<CsvColumn<Row>> EarlierColumns() {
  std::vector<CsvColumn<Row>> columns;
  for (const CsvColumn<Row>& c : kColumns) {
    if (c.name != "drift") columns.push_back(c);
  }
  return columns;
}

// The reference trajectories of one scenario, computed on first use.
class References {
 public:
  References(const Scenario& scenario, const SweepOptions& options)
      : scenario_(scenario), options_(options) {}

  // the scenario's closed form, or `method` converged; sets `uncertainty` (m)
  const RunRecord& For(const Method& method, double& uncertainty) {
    if (scenario_.analytic) {
      if (!analytic_) analytic_ = std::make_unique<RunRecord>(AnalyticTrajectory(scenario_));
      uncertainty = 0;
      return *analytic_;
    }
    auto found = converged_.find(method.name);
    if (found == converged_.end()) {
      const double h_ref = *std::min_element(options_.steps.begin(), options_.steps.end()) /
                           options_.reference_divisor;
      Converged c;
      c.fine = RunTrajectory(method, scenario_, h_ref, options_.cpu_limit_s);
      const RunRecord check = RunTrajectory(method, scenario_, 2 * h_ref, options_.cpu_limit_s);
      c.uncertainty = c.fine.failed || check.failed
                          ? -1
                          : CompareTrajectories(check, c.fine, scenario_.length).state;
      found = converged_.emplace(method.name, std::move(c)).first;
    }
    uncertainty = found->second.uncertainty;
    return found->second.fine;
  }

 private:
  struct Converged {
    RunRecord fine;
    double uncertainty = -1;
  };
  const Scenario& scenario_;
  const SweepOptions& options_;
  std::unique_ptr<RunRecord> analytic_;
  std::map<std::string, Converged> converged_;
};

Method HullMethod() { return FindMethod("hull"); }

}  // namespace

TimedCpu TimedCpuSeconds(const Method& method, const Scenario& scenario, double h,
                         const RunRecord& first, double cpu_limit_s) {
  std::vector<double> times = {first.cpu_seconds};
  double total = first.cpu_seconds;
  while (total < kMinTimedCpuSeconds && static_cast<int>(times.size()) < kMaxTimedRuns) {
    const RunRecord again = RunTrajectory(method, scenario, h, cpu_limit_s);
    if (again.failed) break;
    times.push_back(again.cpu_seconds);
    total += again.cpu_seconds;
  }
  const int runs = static_cast<int>(times.size());
  return {Median(std::move(times)), runs};
}

bool MethodApplies(const Method& method, const Scenario& scenario) {
  if (method.external) return true;
  if (method.selection == engine::Selection::kLeastEnergy) return scenario.least_energy_applies;
  if (method.model == engine::ContactModel::kPlanar) return scenario.planar_applies;
  if (method.model == engine::ContactModel::kMultiPatch) return scenario.multipatch_applies;
  return true;
}

std::vector<WorkPrecisionRow> RunWorkPrecision(const std::vector<Scenario>& scenarios,
                                               const std::vector<Method>& methods,
                                               const SweepOptions& options) {
  ECPSIM_DEMAND(options.shard_count >= 1 && options.shard_index >= 1 &&
                options.shard_index <= options.shard_count);
  std::vector<WorkPrecisionRow> rows;
  int group = -1;
  for (const Scenario& scenario : scenarios) {
    References references(scenario, options);
    for (const Method& method : methods) {
      if (!MethodApplies(method, scenario)) continue;
      ++group;
      if (group % options.shard_count != options.shard_index - 1) continue;
      double uncertainty = -1, hull_uncertainty = -1;
      const RunRecord* reference = nullptr;
      const RunRecord* hull_reference = nullptr;
      if (scenario.has_reference) {
        reference = &references.For(method, uncertainty);
        hull_reference = &references.For(HullMethod(), hull_uncertainty);
      }
      const size_t group_start = rows.size();
      for (double h : options.steps) {
        const auto& only = scenario.only_steps;
        if (!only.empty() && std::find(only.begin(), only.end(), h) == only.end()) continue;
        RunRecord run = RunTrajectory(method, scenario, h, options.cpu_limit_s);
        if (!run.failed && run.steps > 0)
          run.cpu_seconds =
              TimedCpuSeconds(method, scenario, h, run, options.cpu_limit_s).cpu_seconds;
        WorkPrecisionRow row;
        row.scenario = scenario.name;
        row.method = method.name;
        row.h = h;
        row.steps = run.steps;
        row.failed = run.failed;
        // a failed run's cost is that of a different computation (its restarts, sub-steps and
        // the step that threw), and a run that simulated no time has none per second
        row.cpu_per_sim_s = run.failed || run.steps == 0 ? -1 : run.cpu_seconds / (run.steps * h);
        row.max_penetration = run.max_penetration;
        row.iterations_mean = run.iterations_mean;
        row.iterations_max = run.iterations_max;
        row.failure = CsvField(run.failure);
        row.reference_uncertainty = uncertainty;
        if (scenario.pusher >= 0 && !run.failed && !run.push_forces.empty()) {
          double worst = 0;
          long breaks = 0;
          for (double f : run.push_forces) {
            worst = std::max(worst, std::abs(f - scenario.push_force) / scenario.push_force);
            breaks += f <= 0;
          }
          row.push_force_error = worst;
          row.push_contact_breaks = static_cast<double>(breaks) / run.push_forces.size();
        }
        if (scenario.measure_drift && !run.failed) row.drift = run.max_drift;
        if (reference != nullptr && !run.failed && !reference->failed) {
          const TrajectoryErrors e = CompareTrajectories(run, *reference, scenario.length);
          row.error_state = e.state;
          row.error_position = e.position;
          row.error_angle = e.angle;
          row.error_velocity = e.velocity;
          row.wrong_mode = scenario.compare_modes ? e.wrong_mode : -1;
          row.stop_time_error = e.stop_time;
        }
        if (hull_reference != nullptr && !scenario.analytic && !run.failed &&
            !hull_reference->failed) {
          row.error_vs_hull = CompareTrajectories(run, *hull_reference, scenario.length).state;
        }
        rows.push_back(row);
      }
      const size_t runs = rows.size() - group_start;
      if (options.progress && runs == 0) {
        options.progress(fmt::format("{} / {}: not run, it is swept only at h = {} s",
                                     scenario.name, method.name,
                                     fmt::join(scenario.only_steps, ", ")));
      }
      if (options.progress && runs > 0) {
        const WorkPrecisionRow& last = rows.back();
        options.progress(
            fmt::format("{} / {}: {} step sizes, at h = {} s {}, {:.3g} CPU s per simulated s{}",
                        scenario.name, method.name, runs, last.h,
                        scenario.has_reference ? fmt::format("error {:.3g} m", last.error_state)
                                               : fmt::format("drift {:.3g} m", last.drift),
                        last.cpu_per_sim_s, last.failed ? " (failed: " + last.failure + ")" : ""));
      }
    }
  }
  return rows;
}

std::string WorkPrecisionCsv(const std::vector<WorkPrecisionRow>& rows) {
  return WriteCsv(kColumns, rows);
}

std::vector<WorkPrecisionRow> ReadWorkPrecisionCsv(const std::string& path) {
  // the earlier header: its rows, without a drift
  std::ifstream file(path);
  std::string header;
  std::getline(file, header);
  std::string earlier;
  for (const CsvColumn<Row>& c : EarlierColumns()) earlier += (earlier.empty() ? "" : ",") + c.name;
  if (header == earlier) return ReadCsv(path, EarlierColumns());
  return ReadCsv(path, kColumns);
}

}  // namespace ecpsim::evaluation
