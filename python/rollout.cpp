#include "python/rollout.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <optional>
#include <system_error>
#include <thread>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/scene_limits.h"

namespace ecpsim::python {
namespace {

// doubles per body and step: force then torque
constexpr int kWrenchSize = 6;

// steps job's simulation on from `progress`, writing its rows; a step that throws ends it,
// recorded in `failure`, and one that `cancel` stops leaves it where it stands
void RunJob(const RolloutJob& job, std::int64_t steps, size_t index, const CancelFlag* cancel,
            RolloutProgress& progress, std::optional<RolloutFailure>& failure) {
  const std::lock_guard<std::mutex> lock(*job.mutex);
  Simulation& sim = *job.sim;
  sim.StopOn(cancel);
  // (the flag is the caller's: the simulation forgets it whatever leaves this scope)
  const std::unique_ptr<Simulation, void (*)(Simulation*)> unhook(
      &sim, [](Simulation* s) { s->StopOn(nullptr); });
  const size_t n = job.scene->bodies.size();
  for (std::int64_t k = progress.steps_done; k < steps; ++k) {
    try {
      // the step's wrenches, as apply_wrench with no point (kinematic rows are zero, checked)
      if (job.controls != nullptr && !progress.controls_pending) {
        const double* row = job.controls + static_cast<size_t>(k) * n * kWrenchSize;
        for (size_t b = 0; b < n; ++b) {
          if (job.scene->bodies[b].IsKinematic()) continue;
          const double* w = row + b * kWrenchSize;
          sim.ApplyWrench(static_cast<int>(b), Eigen::Vector3d(w[0], w[1], w[2]),
                          Eigen::Vector3d(w[3], w[4], w[5]), std::nullopt);
        }
      }
      progress.controls_pending = job.controls != nullptr;
      sim.Step(1);
      progress.controls_pending = false;
    } catch (const Cancelled&) {
      return;
    } catch (const std::exception& e) {
      failure = RolloutFailure{index, k, sim.state().t, e.what(), std::current_exception()};
      progress.over = true;
      return;
    } catch (...) {
      failure = RolloutFailure{index, k, sim.state().t, "unknown error", std::current_exception()};
      progress.over = true;
      return;
    }
    // the state after the step (engine::Step commits finite states only)
    const engine::State& state = sim.state();
    const size_t at = static_cast<size_t>(k) * n;
    for (size_t b = 0; b < n; ++b) {
      const engine::BodyState& s = state.bodies[b];
      std::memcpy(job.rows.positions + 3 * (at + b), s.p_WB.data(), 3 * sizeof(double));
      std::memcpy(job.rows.velocities + 3 * (at + b), s.v_WB.data(), 3 * sizeof(double));
      std::memcpy(job.rows.angular_velocities + 3 * (at + b), s.w_WB.data(), 3 * sizeof(double));
      double* q = job.rows.quaternions + 4 * (at + b);
      q[0] = s.Q_WB.w(), q[1] = s.Q_WB.x(), q[2] = s.Q_WB.y(), q[3] = s.Q_WB.z();
    }
    job.rows.time[k] = state.t;
    job.rows.converged[k] = sim.last_report().converged;
    progress.steps_done = k + 1;
  }
  progress.over = true;
}

}  // namespace

void CheckControls(const RolloutJob& job, size_t index, std::int64_t steps) {
  if (job.controls == nullptr) return;
  const size_t n = job.scene->bodies.size();
  for (std::int64_t k = 0; k < steps; ++k) {
    for (size_t b = 0; b < n; ++b) {
      const engine::Body& body = job.scene->bodies[b];
      const double* w = job.controls + (static_cast<size_t>(k) * n + b) * kWrenchSize;
      const auto out_of_magnitude = [](double x) { return !engine::OutOfMagnitude(x).empty(); };
      const double* first_bad = std::find_if(w, w + kWrenchSize, out_of_magnitude);
      const bool bad = first_bad != w + kWrenchSize;
      const bool pushes_kinematic =
          body.IsKinematic() && std::any_of(w, w + kWrenchSize, [](double x) { return x != 0; });
      if (!bad && !pushes_kinematic) continue;
      // the message, made for the row that fails only
      const std::string where = fmt::format(
          "rollout: controls[{}, {}, {}] (body '{}' of simulation {} on its step {}) = [{}, {}, "
          "{}, {}, {}, {}]",
          index, k, b, body.name, index, k + 1, w[0], w[1], w[2], w[3], w[4], w[5]);
      if (bad) {
        throw InputError(fmt::format("{}: expected force (N) and torque (N·m), each {}", where,
                                     engine::OutOfMagnitude(*first_bad)));
      }
      throw InputError(
          fmt::format("{}: a kinematic body: expected zeros (a kinematic body follows its "
                      "motion; set_kinematic_target moves it)",
                      where));
    }
  }
}

std::vector<RolloutFailure> Rollout(const std::vector<RolloutJob>& jobs, std::int64_t steps,
                                    int threads, const CancelFlag* cancel,
                                    std::vector<RolloutProgress>& progress) {
  ECPSIM_DEMAND(steps >= 1 && threads >= 1 && progress.size() == jobs.size());
  if (jobs.empty()) return {};
  std::vector<std::optional<RolloutFailure>> failed(jobs.size());
  // each thread takes the next job until none is left (scenes of different cost balance), or
  // the flag is raised
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t i = next.fetch_add(1); i < jobs.size(); i = next.fetch_add(1)) {
      if (cancel != nullptr && cancel->raised()) return;
      if (!progress[i].over) RunJob(jobs[i], steps, i, cancel, progress[i], failed[i]);
    }
  };
  std::vector<std::thread> pool;
  const size_t extra = std::min(jobs.size(), static_cast<size_t>(threads)) - 1;
  for (size_t t = 0; t < extra; ++t) {
    try {
      pool.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the ones running take the remaining jobs
    }
  }
  work();
  for (std::thread& thread : pool) thread.join();

  std::vector<RolloutFailure> failures;
  for (std::optional<RolloutFailure>& f : failed) {
    if (f) failures.push_back(std::move(*f));
  }
  return failures;
}

}  // namespace ecpsim::python
