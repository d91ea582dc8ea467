#include "evaluation/work_precision.h"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "common/errors.h"
#include "evaluation/csv_file.h"
#include "evaluation/error_metrics.h"
#include "evaluation/trajectory_run.h"

namespace ecpsim::evaluation {
namespace {

const std::vector<std::string> kHeader = {"scenario",
                                          "method",
                                          "h",
                                          "steps",
                                          "failed",
                                          "cpu_per_sim_s",
                                          "error_state",
                                          "error_position",
                                          "error_angle",
                                          "error_velocity",
                                          "wrong_mode",
                                          "stop_time_error",
                                          "error_vs_hull",
                                          "reference_uncertainty",
                                          "max_penetration",
                                          "iterations_mean",
                                          "iterations_max",
                                          "push_force_error",
                                          "push_contact_breaks",
                                          "failure"};

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

std::string Number(double value) { return fmt::format("{:.9g}", value); }

}  // namespace

bool MethodApplies(const Method& method, const Scenario& scenario) {
  if (method.external) return true;
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
      const RunRecord& reference = references.For(method, uncertainty);
      const RunRecord& hull_reference = references.For(HullMethod(), hull_uncertainty);
      for (double h : options.steps) {
        const RunRecord run = RunTrajectory(method, scenario, h, options.cpu_limit_s);
        WorkPrecisionRow row;
        row.scenario = scenario.name;
        row.method = method.name;
        row.h = h;
        row.steps = run.steps;
        row.failed = run.failed;
        row.cpu_per_sim_s = run.cpu_seconds / std::max(1e-300, run.steps * h);
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
        if (!run.failed && !reference.failed) {
          const TrajectoryErrors e = CompareTrajectories(run, reference, scenario.length);
          row.error_state = e.state;
          row.error_position = e.position;
          row.error_angle = e.angle;
          row.error_velocity = e.velocity;
          row.wrong_mode = scenario.compare_modes ? e.wrong_mode : -1;
          row.stop_time_error = e.stop_time;
        }
        if (!scenario.analytic && !run.failed && !hull_reference.failed) {
          row.error_vs_hull = CompareTrajectories(run, hull_reference, scenario.length).state;
        }
        rows.push_back(row);
      }
      if (options.progress) {
        const WorkPrecisionRow& last = rows.back();
        options.progress(
            fmt::format("{} / {}: {} step sizes, at h = {} s error {:.3g} m, {:.3g} "
                        "CPU s per simulated s{}",
                        scenario.name, method.name, options.steps.size(), last.h, last.error_state,
                        last.cpu_per_sim_s, last.failed ? " (failed: " + last.failure + ")" : ""));
      }
    }
  }
  return rows;
}

std::string WorkPrecisionCsv(const std::vector<WorkPrecisionRow>& rows) {
  std::string csv;
  for (size_t i = 0; i < kHeader.size(); ++i) csv += (i ? "," : "") + kHeader[i];
  csv += "\n";
  for (const WorkPrecisionRow& r : rows) {
    csv +=
        fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", r.scenario,
                    r.method, Number(r.h), r.steps, r.failed ? 1 : 0, Number(r.cpu_per_sim_s),
                    Number(r.error_state), Number(r.error_position), Number(r.error_angle),
                    Number(r.error_velocity), Number(r.wrong_mode), Number(r.stop_time_error),
                    Number(r.error_vs_hull), Number(r.reference_uncertainty),
                    Number(r.max_penetration), Number(r.iterations_mean), r.iterations_max,
                    Number(r.push_force_error), Number(r.push_contact_breaks), CsvField(r.failure));
  }
  return csv;
}

std::vector<WorkPrecisionRow> ReadWorkPrecisionCsv(const std::string& path) {
  const CsvFile file = ReadCsvFile(path, kHeader);
  std::vector<WorkPrecisionRow> rows;
  for (size_t i = 0; i < file.rows.size(); ++i) {
    WorkPrecisionRow r;
    int c = 0;
    r.scenario = file.rows[i][c++];
    r.method = file.rows[i][c++];
    r.h = file.Number(i, c++);
    r.steps = static_cast<long>(file.Number(i, c++));
    r.failed = file.Number(i, c++) != 0;
    r.cpu_per_sim_s = file.Number(i, c++);
    r.error_state = file.Number(i, c++);
    r.error_position = file.Number(i, c++);
    r.error_angle = file.Number(i, c++);
    r.error_velocity = file.Number(i, c++);
    r.wrong_mode = file.Number(i, c++);
    r.stop_time_error = file.Number(i, c++);
    r.error_vs_hull = file.Number(i, c++);
    r.reference_uncertainty = file.Number(i, c++);
    r.max_penetration = file.Number(i, c++);
    r.iterations_mean = file.Number(i, c++);
    r.iterations_max = static_cast<int>(file.Number(i, c++));
    r.push_force_error = file.Number(i, c++);
    r.push_contact_breaks = file.Number(i, c++);
    r.failure = file.rows[i][c++];
    rows.push_back(r);
  }
  return rows;
}

}  // namespace ecpsim::evaluation
