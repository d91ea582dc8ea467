#include "app/simulation_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/checkpoint.h"
#include "app/interrupt.h"
#include "app/trajectory_writer.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "engine/island_threads.h"
#include "engine/report/penetration.h"
#include "engine/scene_limits.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// the progress bar is redrawn at most this often
constexpr double kProgressInterval = 0.1;  // s of wall time
constexpr int kProgressWidth = 40;         // characters

long PlannedSteps(const engine::Scene& scene) {
  const std::string problem = engine::StepCountProblem(scene.duration, scene.h);
  if (!problem.empty()) {
    throw InputError(fmt::format("{}: duration = {}, h = {}: expected {}", scene.source,
                                 scene.duration, scene.h, problem));
  }
  return engine::PlannedSteps(scene.duration, scene.h);
}

void DrawProgress(double fraction, double t) {
  const int filled = static_cast<int>(fraction * kProgressWidth);
  std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.3f s", std::string(filled, '#').c_str(),
               std::string(kProgressWidth - filled, ' ').c_str(), static_cast<int>(fraction * 100),
               t);
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
  // body-steps per model that solved them (trajectory.csv's model columns), e.g. {"planar": 380,
  // "hull": 20}; models that solved none are left out
  nlohmann::json models = nlohmann::json::object();
  for (int m = 0; m < engine::kNumStepModels; ++m) {
    if (s.model_steps[m] > 0)
      models[engine::StepModelName(static_cast<engine::StepModel>(m))] = s.model_steps[m];
  }
  json["models"] = models;
  json["sleeping_body_steps"] = s.sleeping_body_steps;
  if (s.interrupt_signal != 0) {
    json["signal"] = SignalName(s.interrupt_signal);
  }
  if (s.resumed_from_step >= 0) {
    json["resumed_from_step"] = s.resumed_from_step;
  }
  if (!s.error.empty()) {
    json["error"] = s.error;
  }
  WriteFileAtomically(path, json.dump(2) + "\n");
}

}  // namespace

void RemoveCheckpoint(const std::string& out_dir) {
  std::error_code error;  // none there is the usual case
  fs::remove(fs::path(out_dir) / "checkpoint.json", error);
}

RunSummary RunSimulation(const engine::LoadedScene& loaded, const std::string& out_dir,
                         const RunSetup& setup) {
  const engine::Scene& scene = loaded.scene;
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir)) {
    throw InputError(
        fmt::format("output folder {}: cannot create it ({}); expected a writable "
                    "path",
                    out_dir, error.message()));
  }
  // refuse a FIFO, symlink or folder at summary.json now, not after the whole run
  const std::string summary_path = (fs::path(out_dir) / "summary.json").string();
  const std::string checkpoint_path = (fs::path(out_dir) / "checkpoint.json").string();
  RequireReplaceable(summary_path);
  RequireReplaceable(checkpoint_path);
  const Clock::time_point start = Clock::now();
  RunSummary summary;
  summary.planned_steps = PlannedSteps(scene);

  const Checkpoint* resume = setup.resume;
  engine::State state = resume ? resume->state : engine::InitialState(scene);
  RunTotals totals = resume ? resume->totals : RunTotals();
  TrajectoryWriter writer(scene, (fs::path(out_dir) / "trajectory.csv").string(),
                          resume ? std::optional<long>(resume->rows) : std::nullopt);
  const engine::PenetrationProbe probe(scene);
  double last_drawn = -1;
  std::exception_ptr failure;
  engine::StepReport report;  // of the step that led to `state`
  report.converged = true;
  bool row_written = true;               // the trajectory's last row is `state`
  long rows_on_cadence = writer.rows();  // rows that an uninterrupted run also writes
  bool stopped_in_step = false;          // engine::Step threw: `state` is the last good one

  try {
    if (!resume) {
      writer.Write(state, report);
      rows_on_cadence = writer.rows();
      totals.max_penetration = probe.MaxDepth(scene, state);
      if (setup.observer) setup.observer(state, engine::StepReport{});
    }
    engine::StepWorkspace workspace;
    engine::IslandThreadsOf(workspace).SetThreads(setup.threads);
    engine::StopStepsOn(workspace, &InterruptFlag());
    for (long k = totals.steps + 1; k <= summary.planned_steps; ++k) {
      // a signal stops the run between steps, or in one (app/interrupt.h)
      if (const int signal = InterruptSignal(); signal != 0) {
        summary.interrupt_signal = signal;
        break;
      }
      const Clock::time_point before = Clock::now();
      try {
        report = engine::Step(scene, state, workspace);
      } catch (const Cancelled&) {
        // a signal stopped the step in progress: the state is the last step's, as between steps
        summary.interrupt_signal = InterruptSignal();
        break;
      } catch (...) {
        stopped_in_step = true;
        throw;
      }
      totals.step_us.Add(std::chrono::duration<double, std::micro>(Clock::now() - before).count());

      totals.steps = k;
      totals.all_converged = totals.all_converged && report.converged;
      totals.retries += report.retries;
      totals.iterations += report.iterations;
      totals.iterations_max = std::max(totals.iterations_max, report.iterations);
      totals.residual_max = std::max(totals.residual_max, report.residual);
      totals.substeps_max = std::max(totals.substeps_max, report.substeps);
      for (engine::StepModel model : report.models) ++totals.model_steps[static_cast<int>(model)];
      totals.sleeping_body_steps += report.sleeping_bodies;
      totals.max_penetration = std::max(totals.max_penetration, probe.MaxDepth(scene, state));
      row_written = k % loaded.output.every == 0 || k == summary.planned_steps;
      if (row_written) {
        writer.Write(state, report);
        rows_on_cadence = writer.rows();
      }
      if (setup.observer) setup.observer(state, report);
      if (setup.progress) {
        const double wall = std::chrono::duration<double>(Clock::now() - start).count();
        if (wall - last_drawn >= kProgressInterval || k == summary.planned_steps) {
          DrawProgress(static_cast<double>(k) / summary.planned_steps, state.t);
          last_drawn = wall;
        }
      }
    }
  } catch (const engine::SolverFailure& e) {
    summary.failures = 1;
    summary.error = e.what();
    failure = std::current_exception();
  } catch (const std::exception& e) {
    // bad input found mid-run (a load expression going non-finite): outputs stay valid too
    summary.error = e.what();
    failure = std::current_exception();
  }
  if (setup.progress) {
    std::fputc('\n', stderr);
  }

  // a run that stopped early ends its trajectory at the state it stopped in, as the summary does,
  // and leaves that state in checkpoint.json
  const bool stopped_early = summary.interrupt_signal != 0 || stopped_in_step;
  if (stopped_early && !row_written) {
    writer.Write(state, report);
  }
  writer.Finish();
  // wall time of the whole run, the earlier parts of a resumed one included
  totals.wall_s += std::chrono::duration<double>(Clock::now() - start).count();
  if (stopped_early) {
    const Checkpoint checkpoint{setup.origin, rows_on_cadence, totals, state};
    WriteCheckpoint(checkpoint_path, checkpoint);
  } else if (!failure && !setup.keep_checkpoint) {
    // the run is complete: nothing is left to resume
    RemoveCheckpoint(out_dir);
  }

  summary.steps = totals.steps;
  summary.t_end = state.t;
  summary.rows = writer.rows();
  summary.retries = totals.retries;
  summary.iterations_mean =
      totals.steps > 0 ? static_cast<double>(totals.iterations) / totals.steps : 0.0;
  summary.iterations_max = totals.iterations_max;
  summary.residual_max = totals.residual_max;
  summary.substeps_max = totals.substeps_max;
  summary.model_steps = totals.model_steps;
  summary.sleeping_body_steps = totals.sleeping_body_steps;
  summary.max_penetration = totals.max_penetration;
  summary.median_step_us = totals.step_us.Median();
  summary.converged = totals.all_converged && !failure && summary.interrupt_signal == 0;
  summary.resumed_from_step = resume ? resume->totals.steps : -1;
  summary.wall_s = totals.wall_s;
  WriteSummary(scene, summary, summary_path);
  if (failure) {
    std::rethrow_exception(failure);
  }
  return summary;
}

}  // namespace ecpsim::app
