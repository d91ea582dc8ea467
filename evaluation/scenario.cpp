#include "evaluation/scenario.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "evaluation/clutter_bin.h"
#include "geometry/paper_bodies.h"

namespace ecpsim::evaluation {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.8;  // m/s², the scenes' gravity

engine::Friction CoulombFriction(double mu, double torsion_radius) {
  return engine::Friction{mu, 1, 1, torsion_radius};
}

// a box sliding on its 0.2 × 0.2 face, thrown at 1 m/s at 30° to its edges (between friction
// directions of a 4- or 8-sided cone) with μ = 0.3: stops after v0/(μg) = 0.340 s
Scenario Slide() {
  const double mu = 0.3, v0 = 1.0, angle = kPi / 6;
  const Vector3d size(0.2, 0.2, 0.1);
  engine::Body box = engine::MakeBoxBody(size, 1.0);
  const Vector3d u(std::cos(angle), std::sin(angle), 0);
  box.p0 = Vector3d(0, 0, size.z() / 2);
  box.v0 = v0 * u;
  Scenario s;
  s.name = "slide";
  s.description = "box sliding at 1 m/s, 30° to its edges, mu = 0.3 (closed form)";
  s.scene = engine::MakeGroundScene({box}, 0.01, CoulombFriction(mu, 0.0765));
  s.scene.duration = 0.5;
  s.length = 0.5 * size.norm();
  s.stop_time = v0 / (mu * kG);
  const Vector3d p0 = box.p0;
  const double stop = s.stop_time;
  s.analytic = [=](double t) {
    const double tau = std::min(t, stop);
    engine::BodyState b;
    b.p_WB = p0 + (v0 * tau - 0.5 * mu * kG * tau * tau) * u;
    b.v_WB = (v0 - mu * kG * tau) * u;
    return b;
  };
  s.planar_applies = true;
  return s;
}

// a square plate spinning flat at 10 rad/s: uniform pressure gives the friction moment μ m g r̄
// (r̄ the footprint's mean radius), so ω falls linearly; ecpsim's torsion e_r is set to r̄,
// the exact ellipsoid for this footprint
Scenario Spin() {
  const double mu = 0.3, w0 = 10.0, side = 0.2, thickness = 0.02, mass = 1.0;
  engine::Body plate = engine::MakeBoxBody(Vector3d(side, side, thickness), mass, "plate");
  plate.p0 = Vector3d(0, 0, thickness / 2);
  plate.w0 = Vector3d(0, 0, w0);
  const double r_mean = MeanRadiusOfRectangle(side, side);
  const double alpha = mu * mass * kG * r_mean / plate.inertia(2, 2);  // rad/s²
  Scenario s;
  s.name = "spin";
  s.description =
      "square plate spinning flat at 10 rad/s, mu = 0.3, uniform pressure (closed form)";
  s.scene = engine::MakeGroundScene({plate}, 0.01, CoulombFriction(mu, r_mean));
  s.scene.duration = 0.5;
  s.length = side / std::sqrt(2.0);
  s.stop_time = w0 / alpha;
  const Vector3d p0 = plate.p0;
  const double stop = s.stop_time;
  s.analytic = [=](double t) {
    const double tau = std::min(t, stop);
    engine::BodyState b;
    b.p_WB = p0;
    b.Q_WB = Eigen::Quaterniond(
        Eigen::AngleAxisd(w0 * tau - 0.5 * alpha * tau * tau, Vector3d::UnitZ()));
    b.w_WB = Vector3d(0, 0, w0 - alpha * tau);
    return b;
  };
  s.planar_applies = true;
  return s;
}

// tip or slide: a 0.2 m cube pushed with F = 2 μ m g on its back face 5 cm above the CM slides
// without tipping (the normal force's centre sits 6 cm ahead of the CM, inside the 10 cm
// half-footprint), accelerating at F/m − μg from rest
Scenario PushSlide() {
  const double mu = 0.3, mass = 1.0, side = 0.2;
  engine::Body cube = engine::MakeBoxBody(Vector3d::Constant(side), mass, "cube");
  cube.p0 = Vector3d(0, 0, side / 2);
  const double force = 2 * mu * mass * kG;
  engine::Load push;
  push.x = engine::TimeFunction(force);
  push.at_point = true;
  push.point_B = Vector3d(-side / 2, 0, 0.05);
  Scenario s;
  s.name = "push_slide";
  s.description = "cube pushed at 2 mu m g, 5 cm above its CM: slides, must not tip (closed form)";
  s.scene = engine::MakeGroundScene({cube}, 0.01, CoulombFriction(mu, 0.0765));
  s.scene.loads = {push};
  s.scene.duration = 0.5;
  s.length = side * std::sqrt(3.0) / 2;
  const double a = force / mass - mu * kG;
  const Vector3d p0 = cube.p0;
  s.analytic = [=](double t) {
    engine::BodyState b;
    b.p_WB = p0 + Vector3d(0.5 * a * t * t, 0, 0);
    b.v_WB = Vector3d(a * t, 0, 0);
    return b;
  };
  s.planar_applies = true;
  return s;
}

// the paper's desk standing still on its four feet for 1 s: any motion is drift or jitter
Scenario Rest() {
  engine::Body desk = engine::MakeMeshBody(geometry::MakeDeskMesh(), 15, "desk");
  double lowest = 0;
  for (const Vector3d& v : desk.mesh.vertices) lowest = std::min(lowest, v.z());
  desk.p0 = Vector3d(0, 0, -lowest);  // feet exactly on z = 0
  Scenario s;
  s.name = "rest";
  s.description = "the paper's desk at rest on four feet for 1 s (closed form: no motion)";
  s.scene = engine::MakeGroundScene({desk}, 0.01, CoulombFriction(0.22, 0.1));
  s.scene.duration = 1;
  s.length = 0.35;
  const Vector3d p0 = desk.p0;
  s.analytic = [=](double) {
    engine::BodyState b;
    b.p_WB = p0;
    return b;
  };
  s.planar_applies = true;
  return s;
}

// one of the paper's scenes, cut to `duration`
Scenario PaperScene(const std::string& scenes_dir, const std::string& name, double duration,
                    double length, const std::string& description) {
  Scenario s = SceneScenario(scenes_dir, name, name + ".yaml", "", duration, length, description);
  s.multipatch_applies = !s.scene.bodies[0].parts.empty();
  return s;
}

// the closed form of a body at rest: its start, no motion at all, from t = 0
void MeasureAgainstRest(Scenario& s) {
  const engine::BodyState start = engine::InitialState(s.scene).bodies[s.body];
  s.analytic = [=](double) {
    engine::BodyState b = start;
    b.v_WB = b.w_WB = Vector3d::Zero();
    return b;
  };
  s.stop_time = 0;
}

// scenes/stack.yaml: three boxes stacked at rest; the top box is measured, and the closed form
// is no motion at all (the drift test)
Scenario Stack(const std::string& scenes_dir) {
  Scenario s = SceneScenario(scenes_dir, "stack", "stack.yaml", "top", kBodyScenarioDuration, 0.1,
                             "three boxes stacked at rest, the top one measured (closed form: "
                             "no motion)");
  MeasureAgainstRest(s);
  s.least_energy_applies = true;
  return s;
}

// a scene whose kinematic pusher moves at constant velocity and reaches the measured body, the
// first of the bodies it pushes, after gap / speed; from then on the bodies move at the pusher's
// speed and its force is their whole ground friction Σ μ m g (closed form: a sticking push)
Scenario Push(const std::string& scenes_dir, const std::string& name, const std::string& file,
              const std::string& body, double duration, double length,
              const std::string& description) {
  Scenario s = SceneScenario(scenes_dir, name, file, body, duration, length, description);
  const auto& bodies = s.scene.bodies;
  const auto pusher = std::find_if(bodies.begin(), bodies.end(),
                                   [](const engine::Body& b) { return b.IsKinematic(); });
  ECPSIM_DEMAND(pusher != bodies.end());
  const engine::BodyState pushed = engine::InitialState(s.scene).bodies[s.body];
  const engine::KinematicPose start = pusher->motion->PoseAt(0);
  const Vector3d velocity = pusher->motion->StepTwist(0, s.scene.h).v;
  // the gap between the pusher's leading face and the pushed body's back face along the push
  const Vector3d u = velocity.normalized();
  const double pusher_front =
      u.dot(start.p) + u.dot(start.q * pusher->hull->Support(start.q.inverse() * u));
  const double pushed_back =
      u.dot(pushed.p_WB) +
      u.dot(pushed.Q_WB * bodies[s.body].hull->Support(pushed.Q_WB.inverse() * -u));
  const double contact_time = (pushed_back - pusher_front) / velocity.norm();
  // pushed at constant speed, the bodies' friction on the ground is the whole push: Σ μ m g
  s.pusher = static_cast<int>(pusher - bodies.begin());
  s.push_direction = u;
  s.push_contact_time = contact_time;
  for (const engine::ContactPair& pair : s.scene.contacts) {
    if (!pair.WithBody() && !bodies[pair.body].IsKinematic()) {
      s.push_force += pair.friction.mu * bodies[pair.body].mass * s.scene.gravity.norm();
    }
  }
  s.analytic = [=](double t) {
    engine::BodyState b = pushed;
    if (t > contact_time) {
      b.p_WB += (t - contact_time) * velocity;
      b.v_WB = velocity;
    }
    return b;
  };
  return s;
}

// scenes/push_box.yaml: the pusher's face reaches the box after 0.1 s and from then on carries
// it at its own speed; its force is μ m g
Scenario PushBox(const std::string& scenes_dir) {
  Scenario s = Push(scenes_dir, "push_box", "push_box.yaml", "box", kBodyScenarioDuration, 0.15,
                    "flat pusher at 0.1 m/s pushing a box through its CM, mu = "
                    "0.3 (closed form: the box at the pusher's speed)");
  s.least_energy_applies = true;
  return s;
}

// scenes/pyramid.yaml: ten boxes stacked 4-3-2-1 at rest; the top box is measured against no
// motion at all, and every box's drift from its start is measured
Scenario Pyramid(const std::string& scenes_dir) {
  Scenario s =
      SceneScenario(scenes_dir, "pyramid", "pyramid.yaml", "top", kManyBodyScenarioDuration, 0.1,
                    "ten boxes stacked 4-3-2-1 at rest, the top one measured (closed "
                    "form: no motion; drift: every box's)");
  MeasureAgainstRest(s);
  s.measure_drift = true;
  return s;
}

// scenes/train.yaml: a flat pusher drives a row of six touching boxes from t = 0; the first box
// (the one the pusher touches) is measured, the push force is μ Σ m g of the row, and the drift
// is the boxes' displacement across the row (sideways and up: the row buckling or skewing)
Scenario Train(const std::string& scenes_dir) {
  Scenario s = Push(scenes_dir, "train", "train.yaml", "c1", kManyBodyScenarioDuration, 0.1,
                    "flat pusher at 0.1 m/s driving a row of six boxes, mu = 0.3 (closed "
                    "form: the row at the pusher's speed, force mu sum m g)");
  s.measure_drift = true;
  s.drift_projection =
      Eigen::Matrix3d::Identity() - s.push_direction * s.push_direction.transpose();
  return s;
}

// scenes/peg_in_hole.yaml: a peg falls into the hole through a block made of four convex parts
// (engine/README.md, "Bodies made of convex parts"), strikes the hole's wall and stands on the
// table; the peg is measured over the scene's whole run, whatever moves it there (a version of
// the scene has a kinematic finger push it over the hole first), against the converged run
Scenario PegInHole(const std::string& scenes_dir) {
  Scenario s = SceneScenario(scenes_dir, "peg_in_hole", "peg_in_hole.yaml", "peg",
                             std::numeric_limits<double>::infinity() /* its own duration */, 0,
                             "a peg falling into the hole through a block of four convex parts, "
                             "1 mm of clearance a side (converged reference)");
  // the orientation error's lever: the peg's farthest point from its CM
  for (const Vector3d& v : s.scene.bodies[s.body].hull->Tessellate().vertices)
    s.length = std::max(s.length, v.norm());
  return s;
}

// a pile that falls or is dropped: no reference, and every body's drift from `settle_time` (s),
// swept at the shipped scenes' steps only
void MeasureThePileAtRest(Scenario& s, double settle_time) {
  s.has_reference = false;
  s.compare_modes = false;
  s.measure_drift = true;
  s.drift_from = settle_time;
  s.only_steps = kPileSteps;
}

// ClutterBinScene's bin of `boxes` boxes: no reference (where each box lands depends on every
// collision on its way down), so the cost, the penetration, the failures and the drift at rest
// are measured, every box's from kClutterSettleTime on
Scenario Clutter(const std::string& name, int boxes) {
  Scenario s;
  s.name = name;
  s.description = fmt::format(
      "{} boxes (edges 4-9 cm, 500 kg/m^3, mu = 0.4) dropped into a 0.6 m bin (no reference; "
      "drift: every box from {:g} s, when the pile has settled)",
      boxes, kClutterSettleTime);
  s.scene = ClutterBinScene(boxes, kClutterSeed, 0.01);
  s.length = kClutterEdgeMax;
  MeasureThePileAtRest(s, kClutterSettleTime);
  return s;
}

// scenes/dominoes.yaml run on to 1.5 s: the cascade, the landings and the settled pile. No
// reference (the pile's load split is statically indeterminate, and a converged run of its
// landings would take hours); the drift at rest is every block's from kDominoesSettleTime on
Scenario Dominoes(const std::string& scenes_dir) {
  Scenario s = SceneScenario(scenes_dir, "dominoes", "dominoes.yaml", "d9", kDominoesDuration, 0.1,
                             "nine dominoes toppling and settling in a pile (no reference; "
                             "drift: every block from 1 s, when the pile has settled)");
  s.scene.duration = kDominoesDuration;
  MeasureThePileAtRest(s, kDominoesSettleTime);
  return s;
}

}  // namespace

Scenario SceneScenario(const std::string& scenes_dir, const std::string& name,
                       const std::string& file, const std::string& body, double duration,
                       double length, const std::string& description) {
  Scenario s;
  s.name = name;
  s.description = description;
  const std::string path = (std::filesystem::path(scenes_dir) / file).string();
  s.scene = engine::LoadScene(path).scene;
  s.scene.duration = std::min(s.scene.duration, duration);
  s.length = length;
  if (!body.empty()) {
    const auto& bodies = s.scene.bodies;
    const auto found = std::find_if(bodies.begin(), bodies.end(),
                                    [&](const engine::Body& b) { return b.name == body; });
    if (found == bodies.end())
      throw InputError(
          fmt::format("{}: no body '{}' (the {} scenario measures it)", path, body, name));
    s.body = static_cast<int>(found - bodies.begin());
  }
  return s;
}

double MeanRadiusOfRectangle(double a, double b) {
  // ∫∫ over the quarter [0,p]×[0,q] of |r| = (2pqd + p³ ln((q+d)/p) + q³ ln((p+d)/q)) / 6
  const double p = a / 2, q = b / 2, d = std::hypot(p, q);
  const double quarter =
      (2 * p * q * d + p * p * p * std::log((q + d) / p) + q * q * q * std::log((p + d) / q)) / 6;
  return quarter / (p * q);
}

std::vector<std::string> WorkPrecisionScenarioNames() {
  return {"slide",       "spin",     "push_slide", "rest",      "desk",    "tbar",
          "dumbbell",    "stack",    "push_box",   "tbar_push", "pyramid", "train",
          "peg_in_hole", "dominoes", "clutter",    "clutter96"};
}

std::vector<Scenario> WorkPrecisionScenarios(const std::string& scenes_dir,
                                             double converged_duration) {
  std::vector<Scenario> scenarios = {Slide(), Spin(), PushSlide(), Rest()};
  Scenario desk = PaperScene(scenes_dir, "desk", converged_duration, 0.35,
                             "the paper's desk pushed and twisted (converged reference)");
  desk.planar_applies = true;
  scenarios.push_back(desk);
  scenarios.push_back(PaperScene(scenes_dir, "tbar", converged_duration, 0.25,
                                 "T-bar: point, two-point and non-convex patch contact "
                                 "(converged reference)"));
  Scenario dumbbell = PaperScene(scenes_dir, "dumbbell", converged_duration, 0.2,
                                 "dumbbell rolling on its rims (converged reference)");
  dumbbell.compare_modes = false;
  scenarios.push_back(dumbbell);
  scenarios.push_back(Stack(scenes_dir));
  scenarios.push_back(PushBox(scenes_dir));
  // the paper's motivating figure: a finger pushes and turns the T-bar on the table; no closed
  // form, the converged reference
  Scenario tbar_push =
      SceneScenario(scenes_dir, "tbar_push", "tbar_push.yaml", "tbar", converged_duration, 0.25,
                    "a kinematic finger pushing and turning the T-bar on the "
                    "table (converged reference)");
  tbar_push.least_energy_applies = true;
  scenarios.push_back(tbar_push);
  scenarios.push_back(Pyramid(scenes_dir));
  scenarios.push_back(Train(scenes_dir));
  scenarios.push_back(PegInHole(scenes_dir));
  scenarios.push_back(Dominoes(scenes_dir));
  scenarios.push_back(Clutter("clutter", 24));
  scenarios.push_back(Clutter("clutter96", 96));
  return scenarios;
}

}  // namespace ecpsim::evaluation
