#include "evaluation/stability_map.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_yaml.h"
#include "evaluation/csv_file.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/paper_bodies.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::AngleAxisd;
using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;
constexpr double kStartGap = 1e-3;   // m, lowest vertex above the ground at t = 0
constexpr double kLateWindow = 0.5;  // s, the "at rest" window at the end of each run

// body 0 posed with orientation q, its lowest vertex kStartGap above z = 0, thrown with v
Scenario Thrown(engine::Body body, const Eigen::Quaterniond& q, const Vector3d& v, double mu,
                double torsion, double duration, double length) {
  double lowest = INFINITY;
  for (const Vector3d& x : body.mesh.vertices) lowest = std::min(lowest, (q * x).z());
  body.q0 = q;
  body.p0 = Vector3d(0, 0, kStartGap - lowest);
  body.v0 = v;
  Scenario s;
  s.scene = engine::MakeGroundScene({body}, 0.01, engine::Friction{mu, 1, 1, torsion});
  s.scene.duration = duration;
  s.length = length;
  return s;
}

// the T-bar with its bar `ratio` times as heavy as its stem (1 kg in all): the centre of mass
// and inertia of the two boxes, the mesh and hull moved into that frame
engine::Body TBarWithMassRatio(double ratio) {
  const geometry::TBarParams p;
  geometry::TriangleMesh mesh = geometry::MakeTBarMesh(p);
  double y_top = -INFINITY, z_bottom = INFINITY;
  for (const Vector3d& v : mesh.vertices)
    y_top = std::max(y_top, v.y()), z_bottom = std::min(z_bottom, v.z());
  struct Box {
    Vector3d centre, size;
    double mass;
  };
  const double m_bar = ratio / (1 + ratio), m_stem = 1 / (1 + ratio);
  const Box boxes[] = {
      {Vector3d(0, y_top - p.bar_width / 2, z_bottom + p.thickness / 2),
       Vector3d(p.bar_length, p.bar_width, p.thickness), m_bar},
      {Vector3d(0, y_top - p.bar_width - p.stem_length / 2, z_bottom + p.thickness / 2),
       Vector3d(p.stem_width, p.stem_length, p.thickness), m_stem}};
  const Vector3d cm = (m_bar * boxes[0].centre + m_stem * boxes[1].centre) / (m_bar + m_stem);
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (const Box& b : boxes) {
    const Vector3d s2 = b.size.cwiseProduct(b.size);
    const Vector3d r = b.centre - cm;
    inertia +=
        (b.mass / 12 * Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
    // parallel axis theorem
    inertia += b.mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  engine::Body body;
  body.name = "tbar";
  body.mesh = mesh;
  for (Vector3d& v : body.mesh.vertices) v -= cm;
  body.hull = std::make_shared<geometry::PolyhedralShape>(
      geometry::ComputeConvexHull(body.mesh.vertices, "T-bar"));
  body.mass = 1;
  body.inertia = inertia;
  return body;
}

// s: a push run's length; the contact starts after 1 cm / speed ≤ 0.33 s, so the box has been
// pushed for ≥ 0.67 s when the late window (the last 0.5 s) opens
constexpr double kPushDuration = 1.5;

int PusherOf(const Scenario& scenario) {
  const auto& bodies = scenario.scene.bodies;
  const auto it = std::find_if(bodies.begin(), bodies.end(),
                               [](const engine::Body& b) { return b.IsKinematic(); });
  ECPSIM_DEMAND(it != bodies.end());
  return static_cast<int>(it - bodies.begin());
}

// scenes/push_box.yaml (in `scenes_dir`) with the pusher's velocity scaled to `speed`
Scenario PushAtSpeed(const std::string& scenes_dir, double speed) {
  Scenario s;
  s.name = fmt::format("push_speed_{}", speed);
  s.scene = engine::LoadScene((std::filesystem::path(scenes_dir) / "push_box.yaml").string()).scene;
  s.scene.duration = kPushDuration;
  s.length = 0.15;
  const int pusher = PusherOf(s);
  engine::Body& body = s.scene.bodies[pusher];
  engine::ConstantTwist twist;
  twist.start = body.motion->PoseAt(0);
  twist.v = speed * body.motion->StepTwist(0, s.scene.h).v.normalized();
  body.motion = std::make_shared<engine::KinematicMotion>(twist, body.motion->where());
  s.body = pusher == 0 ? 1 : 0;
  return s;
}

// stability.csv's columns, in order
using Row = StabilityRow;
constexpr int kDigits = 9;  // significant digits of every number
const std::vector<CsvColumn<Row>> kColumns = {
    TextColumn<Row>("map", &Row::map),
    TextColumn<Row>("method", &Row::method),
    NumberColumn<Row>("h", kDigits, &Row::h),
    NumberColumn<Row>("value", kDigits, &Row::value),
    EnumColumn<Row>("outcome", OutcomeName, kOutcomeCount, &Row::outcome),
    NumberColumn<Row>("max_penetration", kDigits, &Row::max_penetration),
    NumberColumn<Row>("energy_gain", kDigits, &Row::energy_gain),
    NumberColumn<Row>("max_speed_late", kDigits, &Row::max_speed_late),
    NumberColumn<Row>("drift_late", kDigits, &Row::drift_late),
    TextColumn<Row>("final_mode", &Row::final_mode),
    TextColumn<Row>("failure", &Row::failure),
};

}  // namespace

const char* OutcomeName(Outcome outcome) {
  switch (outcome) {
    case Outcome::kOk:
      return "ok";
    case Outcome::kSolverFailure:
      return "solver_failure";
    case Outcome::kPenetration:
      return "penetration";
    case Outcome::kEnergyGain:
      return "energy_gain";
    case Outcome::kWrongMode:
      return "wrong_mode";
    case Outcome::kJitter:
      return "jitter";
    case Outcome::kOffSpeed:
      return "off_speed";
  }
  return "unknown";
}

std::vector<StabilityMapSpec> StabilityMaps(const std::string& scenes_dir) {
  StabilityMapSpec impact;
  impact.name = "impact";
  impact.description = "box 0.2 x 0.15 x 0.1 m thrown corner-first at the ground, mu = 0.5";
  impact.value_label = "impact speed (m/s)";
  impact.values = {0.1, 0.3, 1, 3, 10, 30, 100};
  impact.scenario = [](double speed) {
    const engine::Body box = engine::MakeBoxBody(Vector3d(0.2, 0.15, 0.1), 1.0);
    const Eigen::Quaterniond q(AngleAxisd(20 * kDeg, Vector3d::UnitX()) *
                               AngleAxisd(10 * kDeg, Vector3d::UnitY()));
    Scenario s = Thrown(box, q, speed * Vector3d(0.3, 0, -1).normalized(), 0.5, 0.05, 2.0, 0.13);
    s.name = fmt::format("impact_{}", speed);
    return s;
  };

  StabilityMapSpec plate;
  plate.name = "thin_plate";
  plate.description = "0.2 x 0.2 m plate, 1 kg, dropped tilted at 2 m/s, mu = 0.5";
  plate.value_label = "thickness / side";
  plate.values = {0.1, 0.03, 0.01, 0.003, 0.001};
  plate.scenario = [](double aspect) {
    const engine::Body body = engine::MakeBoxBody(Vector3d(0.2, 0.2, 0.2 * aspect), 1.0, "plate");
    const Eigen::Quaterniond q(AngleAxisd(15 * kDeg, Vector3d::UnitX()) *
                               AngleAxisd(5 * kDeg, Vector3d::UnitY()));
    Scenario s = Thrown(body, q, Vector3d(0.5, 0, -2), 0.5, 0.08, 1.5, 0.14);
    s.name = fmt::format("thin_plate_{}", aspect);
    return s;
  };

  StabilityMapSpec tbar;
  tbar.name = "tbar_mass_ratio";
  tbar.description = "T-bar (1 kg) dropped tilted at 1 m/s; bar mass / stem mass varied, mu = 0.5";
  tbar.value_label = "bar mass / stem mass";
  tbar.values = {0.1, 0.3, 1, 3, 10};
  tbar.scenario = [](double ratio) {
    const Eigen::Quaterniond q(AngleAxisd(25 * kDeg, Vector3d::UnitX()) *
                               AngleAxisd(-10 * kDeg, Vector3d::UnitY()));
    Scenario s = Thrown(TBarWithMassRatio(ratio), q, Vector3d(0.5, 0, -1), 0.5, 0.1, 2.0, 0.25);
    s.name = fmt::format("tbar_mass_ratio_{}", ratio);
    return s;
  };

  StabilityMapSpec push;
  push.name = "push_speed";
  push.description =
      "scenes/push_box.yaml: a flat pusher at constant speed pushing a box, mu = 0.3";
  push.value_label = "push speed (m/s)";
  push.values = {0.03, 0.1, 0.3, 1, 3};
  push.scenario = [scenes_dir](double speed) { return PushAtSpeed(scenes_dir, speed); };
  push.classify = [](const RunRecord& run, const Scenario& scenario) {
    const engine::Body& pusher = scenario.scene.bodies[PusherOf(scenario)];
    return ClassifyPush(run, scenario, pusher.motion->StepTwist(0, scenario.scene.h).v,
                        kLateWindow);
  };
  return {impact, plate, tbar, push};
}

Outcome ClassifyPush(const RunRecord& run, const Scenario& scenario,
                     const Eigen::Vector3d& pusher_velocity, double late_window) {
  if (run.failed) return Outcome::kSolverFailure;
  if (run.max_penetration > kPenetrationLimit) return Outcome::kPenetration;
  const double late_start = scenario.scene.duration - late_window;
  for (size_t k = 0; k < run.samples.size(); ++k) {
    if (static_cast<double>(k) * scenario.sample_interval < late_start - 1e-9) continue;
    const Vector3d error = run.samples[k].v_WB - pusher_velocity;
    if (!(error.norm() <= kPushSpeedTolerance * pusher_velocity.norm())) return Outcome::kOffSpeed;
  }
  return Outcome::kOk;
}

Outcome Classify(const RunRecord& run, double initial_kinetic) {
  // energy that grew before a failure is its cause (an overflowing spin ends as a failure)
  const double gain =
      *std::max_element(run.energies.begin(), run.energies.end()) - run.energies.front();
  if (gain > kEnergyGainFraction * initial_kinetic + 1e-6) return Outcome::kEnergyGain;
  if (run.failed) return Outcome::kSolverFailure;
  if (run.max_penetration > kPenetrationLimit) return Outcome::kPenetration;
  if (run.modes.back() != ContactMode::kFace) return Outcome::kWrongMode;
  if (run.max_speed_late > kJitterSpeed || run.drift_late > kJitterDrift) return Outcome::kJitter;
  return Outcome::kOk;
}

std::vector<StabilityRow> RunStabilityMaps(
    const std::vector<StabilityMapSpec>& maps, const std::vector<Method>& methods,
    const std::vector<double>& steps, int shard_index, int shard_count, double cpu_limit_s,
    const std::function<void(const std::string&)>& progress) {
  ECPSIM_DEMAND(shard_count >= 1 && shard_index >= 1 && shard_index <= shard_count);
  std::vector<StabilityRow> rows;
  int group = -1;
  for (const StabilityMapSpec& map : maps) {
    for (const Method& method : methods) {
      // the planar model cannot land a body, and these bodies have no convex parts (the
      // multi-patch model would be the hull model again)
      if (!method.external && (method.model == engine::ContactModel::kPlanar ||
                               method.model == engine::ContactModel::kMultiPatch)) {
        continue;
      }
      ++group;
      if (group % shard_count != shard_index - 1) continue;
      int ok = 0, cells = 0;
      for (double value : map.values) {
        const Scenario scenario = map.scenario(value);
        const engine::Body& body = scenario.scene.bodies[scenario.body];
        const double kinetic = 0.5 * body.mass * body.v0.squaredNorm();
        for (double h : steps) {
          const RunRecord run = RunTrajectory(method, scenario, h, cpu_limit_s, kLateWindow);
          StabilityRow row;
          row.map = map.name;
          row.method = method.name;
          row.h = h;
          row.value = value;
          row.outcome = map.classify ? map.classify(run, scenario) : Classify(run, kinetic);
          row.max_penetration = run.max_penetration;
          row.energy_gain =
              *std::max_element(run.energies.begin(), run.energies.end()) - run.energies.front();
          row.max_speed_late = run.max_speed_late;
          row.drift_late = run.drift_late;
          row.final_mode = ContactModeName(run.modes.back());
          row.failure = CsvField(run.failure);
          ok += row.outcome == Outcome::kOk;
          ++cells;
          rows.push_back(row);
        }
      }
      if (progress) {
        progress(
            fmt::format("stability {} / {}: {} of {} runs ok", map.name, method.name, ok, cells));
      }
    }
  }
  return rows;
}

std::string StabilityCsv(const std::vector<StabilityRow>& rows) { return WriteCsv(kColumns, rows); }

std::vector<StabilityRow> ReadStabilityCsv(const std::string& path) {
  return ReadCsv(path, kColumns);
}

}  // namespace ecpsim::evaluation
