#include "app/simulation_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/interrupt.h"
#include "app/trajectory_writer.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/reservoir_median.h"
#include "engine/penetration.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// duration / h within this relative slack of an integer counts as that integer, so 0.5 / 0.01
// (49.999999999999993 or 50.000000000000007 in floating point) gives 50 steps, not 51
constexpr double kStepCountSlack = 1e-9;
// the progress bar is redrawn at most this often
constexpr double kProgressInterval = 0.1;  // s of wall time
constexpr int kProgressWidth = 40;         // characters

// step counts are exact integers in a double up to 2^53 (t and the progress fraction use them);
// a run that long would take decades anyway
constexpr double kMaxSteps = 9007199254740992.0;  // 2^53

long PlannedSteps(const engine::Scene& scene) {
  const double steps = std::ceil(scene.duration / scene.h * (1 - kStepCountSlack));
  if (!(steps <= kMaxSteps)) {
    throw InputError(fmt::format("{}: duration / h = {} / {} = {:g} steps: expected at most {:g} "
                                 "steps; use a larger h or a shorter duration",
                                 scene.source, scene.duration, scene.h, steps, kMaxSteps));
  }
  return std::max(1L, static_cast<long>(steps));
}

void DrawProgress(double fraction, double t) {
  const int filled = static_cast<int>(fraction * kProgressWidth);
  std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.3f s", std::string(filled, '#').c_str(),
               std::string(kProgressWidth - filled, ' ').c_str(),
               static_cast<int>(fraction * 100), t);
  std::fflush(stderr);
}

void WriteSummary(const engine::Scene& scene, const RunSummary& s, const std::string& path) {
  nlohmann::json json = {
      {"scene", scene.source},
      {"h", scene.h},
      {"duration", scene.duration},
      {"t_end", s.t_end},
      {"planned_steps", s.planned_steps},
      {"steps", s.steps},
      {"rows", s.rows},
      {"converged", s.converged},
      {"interrupted", s.interrupt_signal != 0},
      {"failures", s.failures},
      {"retries", s.retries},
      {"iterations_mean", s.iterations_mean},
      {"iterations_max", s.iterations_max},
      {"residual_max", s.residual_max},
      {"substeps_max", s.substeps_max},
      {"max_penetration", s.max_penetration},
      {"wall_s", s.wall_s},
      {"median_step_us", s.median_step_us},
  };
  if (s.interrupt_signal != 0) {
    json["signal"] = SignalName(s.interrupt_signal);
  }
  if (!s.error.empty()) {
    json["error"] = s.error;
  }
  WriteFileAtomically(path, json.dump(2) + "\n");
}

}  // namespace

RunSummary RunSimulation(const engine::Scene& scene, const std::string& out_dir, bool progress,
                         const StepObserver& observer) {
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir)) {
    throw InputError(fmt::format("output folder {}: cannot create it ({}); expected a writable "
                                 "path",
                                 out_dir, error.message()));
  }
  // refuse a FIFO, symlink or folder at summary.json now, not after the whole run
  const std::string summary_path = (fs::path(out_dir) / "summary.json").string();
  RequireReplaceable(summary_path);
  const Clock::time_point start = Clock::now();
  RunSummary summary;
  summary.planned_steps = PlannedSteps(scene);

  engine::State state = engine::InitialState(scene);
  TrajectoryWriter writer(scene, (fs::path(out_dir) / "trajectory.csv").string());
  const engine::PenetrationProbe probe(scene);
  // nothing is kept per step: memory stays flat however many steps the run takes
  ReservoirMedian step_us;
  long iterations_total = 0;
  double last_drawn = -1;
  std::exception_ptr failure;
  bool every_step_converged = true;

  try {
    engine::StepReport report;
    report.converged = true;
    writer.Write(state, report);
    bool row_written = true;  // the trajectory's last row is `state`
    summary.max_penetration = probe.MaxDepth(scene, state);
    if (observer) observer(state, 0);
    for (long k = 1; k <= summary.planned_steps; ++k) {
      // a signal stops the run between steps (app/interrupt.h)
      if (const int signal = InterruptSignal(); signal != 0) {
        summary.interrupt_signal = signal;
        break;
      }
      const Clock::time_point before = Clock::now();
      report = engine::Step(scene, state);
      step_us.Add(std::chrono::duration<double, std::micro>(Clock::now() - before).count());

      summary.steps = k;
      every_step_converged = every_step_converged && report.converged;
      summary.retries += report.retries;
      iterations_total += report.iterations;
      summary.iterations_max = std::max(summary.iterations_max, report.iterations);
      summary.residual_max = std::max(summary.residual_max, report.residual);
      summary.substeps_max = std::max(summary.substeps_max, report.substeps);
      summary.max_penetration = std::max(summary.max_penetration, probe.MaxDepth(scene, state));
      row_written = k % scene.output.every == 0 || k == summary.planned_steps;
      if (row_written) {
        writer.Write(state, report);
      }
      if (observer) observer(state, report.iterations);
      if (progress) {
        const double wall = std::chrono::duration<double>(Clock::now() - start).count();
        if (wall - last_drawn >= kProgressInterval || k == summary.planned_steps) {
          DrawProgress(static_cast<double>(k) / summary.planned_steps, state.t);
          last_drawn = wall;
        }
      }
    }
    // an interrupted trajectory ends at the state the run stopped in, as the summary does
    if (!row_written) {
      writer.Write(state, report);
    }
    summary.converged = every_step_converged && summary.interrupt_signal == 0;
  } catch (const engine::SolverFailure& e) {
    summary.failures = 1;
    summary.error = e.what();
    failure = std::current_exception();
  } catch (const std::exception& e) {
    // bad input found mid-run (a load expression going non-finite): outputs stay valid too
    summary.error = e.what();
    failure = std::current_exception();
  }
  if (progress) {
    std::fputc('\n', stderr);
  }

  writer.Finish();
  summary.iterations_mean =
      summary.steps > 0 ? static_cast<double>(iterations_total) / summary.steps : 0.0;
  summary.median_step_us = step_us.Median();
  summary.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  summary.t_end = state.t;
  summary.rows = writer.rows();
  WriteSummary(scene, summary, summary_path);
  if (failure) {
    std::rethrow_exception(failure);
  }
  return summary;
}

}  // namespace ecpsim::app
