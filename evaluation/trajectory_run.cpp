#include "evaluation/trajectory_run.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/report/penetration.h"
#include "engine/step_report.h"
#include "evaluation/cpu_budget.h"
#include "geometry/convex_shape.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::Vector3d;

// segments of a smooth hull's tessellation when its vertices stand in for the hull's (the
// dumbbell's 96-gon mesh has as many)
constexpr int kSmoothHullSegments = 96;

std::vector<Vector3d> HullVertices(const geometry::ConvexShape& hull) {
  if (const auto* polyhedron = hull.AsPolyhedron()) {
    return polyhedron->hull().vertices;
  }
  return hull.Tessellate(kSmoothHullSegments).vertices;
}

double Energy(const engine::Scene& scene, int index, const engine::BodyState& b) {
  const engine::Body& body = scene.bodies[index];
  const Eigen::Matrix3d R = b.Q_WB.toRotationMatrix();
  const Eigen::Matrix3d I_W = R * body.inertia * R.transpose();
  const double energy = 0.5 * body.mass * b.v_WB.squaredNorm() + 0.5 * b.w_WB.dot(I_W * b.w_WB) -
                        body.mass * scene.gravity.dot(b.p_WB);
  // a spin growing without bound overflows the energy before the state: the largest double
  // keeps it comparable (and out of the CSV as "inf")
  return std::isfinite(energy) ? energy : std::numeric_limits<double>::max();
}

double Speed(const engine::BodyState& b, double length) {
  return b.v_WB.norm() + length * b.w_WB.norm();
}

// |Δp| + length · (rotation angle between the orientations)
double PoseDistance(const engine::BodyState& a, const engine::BodyState& b, double length) {
  return (a.p_WB - b.p_WB).norm() + length * a.Q_WB.angularDistance(b.Q_WB);
}

int StepsPerSample(const Scenario& scenario, double h) {
  const double ratio = scenario.sample_interval / h;
  const long n = std::lround(ratio);
  if (n < 1 || std::abs(ratio - static_cast<double>(n)) > 1e-9 * ratio) {
    throw InputError(fmt::format(
        "scenario {}: step h = {} s does not divide the sample interval {} s (expected h = "
        "interval / n for a whole n)",
        scenario.name, h, scenario.sample_interval));
  }
  return static_cast<int>(n);
}

int SampleCount(const Scenario& scenario) {
  return static_cast<int>(std::lround(scenario.scene.duration / scenario.sample_interval));
}

}  // namespace

const char* ContactModeName(ContactMode mode) {
  switch (mode) {
    case ContactMode::kNone:
      return "none";
    case ContactMode::kVertex:
      return "vertex";
    case ContactMode::kEdge:
      return "edge";
    case ContactMode::kFace:
      return "face";
  }
  return "unknown";
}

ContactMode ModeOfPose(const engine::Scene& scene, int body, const engine::BodyState& state) {
  const Eigen::Matrix3d R = state.Q_WB.toRotationMatrix();
  std::vector<Vector3d> world;
  for (const Vector3d& v : HullVertices(*scene.bodies[body].hull))
    world.push_back(state.p_WB + R * v);
  ContactMode deepest = ContactMode::kNone;
  for (const engine::ContactPair& pair : scene.contacts) {
    if (pair.body != body || pair.WithBody()) continue;
    const geometry::ConvexShape& obstacle = *scene.obstacles[pair.obstacle].shape;
    std::vector<double> gaps;
    for (const Vector3d& x : world) {
      double gap = -INFINITY;
      for (int i = 0; i < obstacle.NumConstraints(); ++i) gap = std::max(gap, obstacle.Value(i, x));
      gaps.push_back(gap);
    }
    const double lowest = *std::min_element(gaps.begin(), gaps.end());
    if (lowest > kContactDistance) continue;
    std::vector<Vector3d> touching;
    for (size_t k = 0; k < world.size(); ++k) {
      if (gaps[k] <= lowest + kModeSpread) touching.push_back(world[k]);
    }
    ContactMode mode = ContactMode::kVertex;
    if (touching.size() >= 2) {
      // the two farthest-apart touching points span the line; anything off it makes a face
      size_t a = 0, b = 1;
      double widest = -1;
      for (size_t i = 0; i < touching.size(); ++i) {
        for (size_t j = i + 1; j < touching.size(); ++j) {
          const double d = (touching[i] - touching[j]).norm();
          if (d > widest) widest = d, a = i, b = j;
        }
      }
      mode = widest <= kModeSpread ? ContactMode::kVertex : ContactMode::kEdge;
      const Vector3d axis = (touching[b] - touching[a]).normalized();
      for (const Vector3d& x : touching) {
        const Vector3d off = (x - touching[a]) - axis * axis.dot(x - touching[a]);
        if (widest > kModeSpread && off.norm() > kModeSpread) mode = ContactMode::kFace;
      }
    }
    deepest = std::max(deepest, mode);
  }
  return deepest;
}

RunRecord RunTrajectory(const Method& method, const Scenario& scenario, double h,
                        double cpu_limit_s, double late_window) {
  engine::Scene scene = scenario.scene;
  scene.h = h;
  const int per_sample = StepsPerSample(scenario, h);
  const int samples = SampleCount(scenario);
  const long steps = static_cast<long>(samples) * per_sample;
  const long late_steps = std::lround(late_window / h);

  RunRecord run;
  const engine::PenetrationProbe probe(scene);
  std::unique_ptr<Stepper> stepper;
  try {
    stepper = MakeStepper(method, scene);
  } catch (const engine::SolverFailure& failure) {  // a peer that cannot build its model
    run.failed = true;
    run.failure = failure.what();
    return run;
  }
  const int measured = scenario.body;
  auto record = [&](const engine::State& state) {
    const engine::BodyState& b = state.bodies[measured];
    run.samples.push_back(b);
    run.modes.push_back(ModeOfPose(scene, measured, b));
    run.energies.push_back(Energy(scene, measured, b));
  };
  record(stepper->state());
  // the dynamic bodies' places the drift is measured from (Scenario::drift_from)
  std::vector<engine::BodyState> starts = stepper->state().bodies;
  if (scenario.measure_drift) run.max_drift = 0;

  double last_fast_t =
      Speed(stepper->state().bodies[measured], scenario.length) >= kStopSpeed ? 0 : -1;
  engine::BodyState late_start;
  long iterations_sum = 0;
  // the limit stops a step of minutes within a solver iteration of it
  CpuBudget budget(cpu_limit_s);
  stepper->StopOn(budget.flag());
  const auto limit_reached = [&](double t) {
    run.failed = true;
    run.failure = fmt::format("CPU limit of {} s reached at t = {} s", cpu_limit_s, t);
  };
  for (long k = 1; k <= steps; ++k) {
    CpuBudget::Outcome charged = CpuBudget::Outcome::kWithin;
    try {
      charged = budget.Charge([&] { stepper->Step(); });
    } catch (const engine::SolverFailure& failure) {
      run.failed = true;
      run.failure = failure.what();
    } catch (const engine::ModelInvalid& invalid) {
      run.failed = true;
      run.failure = invalid.what();
    }
    run.cpu_seconds = budget.used_s();
    if (run.failed) break;
    // (a step the limit stopped is undone: the state is the last step's)
    if (charged == CpuBudget::Outcome::kStopped) {
      limit_reached(stepper->state().t);
      break;
    }
    const engine::State& state = stepper->state();
    const engine::BodyState& b = state.bodies[measured];
    if (!engine::IsFinite(b)) {
      run.failed = true;
      run.failure = fmt::format("non-finite state at t = {} s", state.t);
      break;
    }
    run.steps = k;
    const int iterations = stepper->iterations();
    iterations_sum += iterations;
    run.iterations_max = std::max(run.iterations_max, iterations);
    run.max_penetration = std::max(run.max_penetration, probe.MaxDepth(scene, state));
    const double speed = Speed(b, scenario.length);
    if (speed >= kStopSpeed) last_fast_t = state.t;
    if (k == steps - late_steps) late_start = b;
    if (k > steps - late_steps) {
      run.max_speed_late = std::max(run.max_speed_late, speed);
      run.drift_late = std::max(run.drift_late, PoseDistance(b, late_start, scenario.length));
    }
    if (k % per_sample == 0) record(state);
    if (scenario.measure_drift && state.t > scenario.drift_from - 0.5 * h) {
      if (state.t < scenario.drift_from + 0.5 * h) starts = state.bodies;
      for (size_t i = 0; i < starts.size(); ++i) {
        if (scene.bodies[i].IsKinematic()) continue;
        const Vector3d moved = state.bodies[i].p_WB - starts[i].p_WB;
        run.max_drift = std::max(run.max_drift, (scenario.drift_projection * moved).norm());
      }
    }
    if (scenario.pusher >= 0 && state.t > scenario.push_contact_time + kPushSettleTime) {
      run.push_forces.push_back(
          scenario.push_direction.dot(stepper->ContactForce(measured, scenario.pusher)));
    }
    if (charged == CpuBudget::Outcome::kSpent) {
      limit_reached(state.t);
      break;
    }
  }
  if (run.steps > 0) run.iterations_mean = static_cast<double>(iterations_sum) / run.steps;
  if (!run.failed && last_fast_t < scene.duration - 0.5 * h) run.stop_time = last_fast_t + h;
  if (last_fast_t < 0) run.stop_time = 0;
  return run;
}

RunRecord AnalyticTrajectory(const Scenario& scenario) {
  ECPSIM_DEMAND(static_cast<bool>(scenario.analytic));
  RunRecord run;
  const int samples = SampleCount(scenario);
  for (int k = 0; k <= samples; ++k) {
    const engine::BodyState b = scenario.analytic(k * scenario.sample_interval);
    run.samples.push_back(b);
    run.modes.push_back(ModeOfPose(scenario.scene, scenario.body, b));
    run.energies.push_back(Energy(scenario.scene, scenario.body, b));
  }
  run.steps = samples;
  run.stop_time = scenario.stop_time;
  return run;
}

}  // namespace ecpsim::evaluation
