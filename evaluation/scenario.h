#pragma once
// The benchmark's scenarios: bodies on the ground, one of them measured, each with a reference
// trajectory, either in closed form (slide, spin, push-slide, rest, stack, push_box, pyramid,
// train) or a converged solution (desk, T-bar, dumbbell, tbar_push, peg_in_hole), or none where
// no step size resolves one path (the dominoes and the clutter bins: their cost, penetration and
// rest are measured).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::evaluation {

struct Scenario {
  std::string name;         // CSV key and chart name: slide, spin, push_slide, rest, desk, …
  std::string description;  // one line for the charts and docs
  engine::Scene scene;      // h is set per run
  int body = 0;             // the body measured (its errors, modes, energy, stop time)
  double sample_interval = 0.02;  // s, errors are taken at multiples of it (every h divides it)
  double length = 0.1;            // m, weights orientation errors: e = |Δp| + length·|Δθ|
  // the closed-form trajectory of the measured body (continuous time); empty: converged
  // reference
  std::function<engine::BodyState(double t)> analytic;
  // false: no reference at all (a pile dropped at random, whose path no step size resolves):
  // the error columns stay −1
  bool has_reference = true;
  double stop_time = -1;        // s, when the motion ends in closed form (< 0: not measured)
  bool planar_applies = false;  // flat on the ground throughout: the planar model applies
  // the body has convex `parts` (else the multi-patch model is the hull model once more)
  bool multipatch_applies = false;
  // contacts between bodies whose islands are small enough for the least-energy selection's
  // dense factorizations (auto-least-energy runs here; alone on the ground it is auto)
  bool least_energy_applies = false;
  // contact modes are compared (not for a smooth hull: a tolerance band on a curved surface
  // makes the mode depend on the band, not on the motion)
  bool compare_modes = true;
  // a push: body `pusher` (≥ 0) pushes the measured body along `push_direction` (world, unit),
  // touching it from `push_contact_time` (s) on, with the steady force `push_force` (N) in closed
  // form (RunRecord::push_forces, WorkPrecisionRow::push_force_error)
  int pusher = -1;
  Eigen::Vector3d push_direction = Eigen::Vector3d::UnitX();
  double push_contact_time = 0;
  double push_force = 0;
  // drift (RunRecord::max_drift, WorkPrecisionRow::drift): every dynamic body's CM displacement
  // from its start, projected by `drift_projection` (world frame), the largest over the bodies
  // and the steps; for scenes of many bodies, where the measured one shows only its own
  bool measure_drift = false;
  Eigen::Matrix3d drift_projection = Eigen::Matrix3d::Identity();
  // s: the step sizes of the sweep this scenario is run at (empty: all of them); a pile without
  // a reference has no error to converge, and at the sweep's finest steps its runs would take
  // hours
  std::vector<double> only_steps;
  // s: the drift is measured from the bodies' places at this time (0: their start; a pile that
  // is dropped: once it has settled, its drift at rest)
  double drift_from = 0;
};

/// s after a push's first contact that its force is not compared: the pusher strikes the body
/// (an impulse m v in the first step) and a soft contact settles; the closed form is the steady
/// push after that
constexpr double kPushSettleTime = 0.1;

/// The work–precision scenarios. `scenes_dir` holds desk.yaml, tbar.yaml, dumbbell.yaml,
/// stack.yaml, push_box.yaml, tbar_push.yaml, pyramid.yaml, train.yaml, peg_in_hole.yaml and
/// dominoes.yaml (desk, tbar, dumbbell and tbar_push are cut to `converged_duration` seconds,
/// stack and push_box to kBodyScenarioDuration, pyramid and train to kManyBodyScenarioDuration,
/// to keep the sweep affordable, peg_in_hole runs its scene's whole duration and measures the
/// body named `peg`, dominoes is run on to kDominoesDuration); clutter and clutter96 are
/// ClutterBinScene's bins of 24 and 96 boxes (seed kClutterSeed).
/// @throws InputError if a scene file is missing or invalid.
std::vector<Scenario> WorkPrecisionScenarios(const std::string& scenes_dir,
                                             double converged_duration = 1.0);

/// The names of WorkPrecisionScenarios(), in its order (without loading any scene).
std::vector<std::string> WorkPrecisionScenarioNames();

/// s: how long the stack and push_box scenarios run in the sweep (the scenes' 10 s and 2 s
/// would make their runs at h = 2e-4 s the sweep's longest).
constexpr double kBodyScenarioDuration = 1.0;

/// s: how long the pyramid and train scenarios run in the sweep: the scenes' whole 2 s (issue
/// 30's rest and push, long enough for the whole row to move at the pusher's speed).
constexpr double kManyBodyScenarioDuration = 2.0;

/// s: how long the dominoes scenario runs (scenes/dominoes.yaml's last block lands flat at 0.72 s)
/// and when its drift at rest is measured from (every block below 1e-5 m/s from 0.8 s on,
/// `ecpsim run scenes/dominoes.yaml --set duration=1.5`).
constexpr double kDominoesDuration = 1.5;
constexpr double kDominoesSettleTime = 1.0;

/// s: the step sizes the dominoes and the clutter bins are swept at (Scenario::only_steps): the
/// shipped scenes' 0.01 and 0.005.
inline const std::vector<double> kPileSteps = {0.01, 0.005};

/// The clutter scenarios' seed: one fixed bin, so that every run and every method drops the same
/// boxes the same way.
constexpr std::uint64_t kClutterSeed = 7;

/// The scenario of a scene file `scenes_dir`/`file` measuring body `body` (by name), cut to
/// `duration`; the reference is `analytic` when given, else the converged solution.
/// @throws InputError if the file is missing or invalid, or has no body of that name.
Scenario SceneScenario(const std::string& scenes_dir, const std::string& name,
                       const std::string& file, const std::string& body, double duration,
                       double length, const std::string& description);

/// Mean distance of the points of an a × b rectangle from its centre (m): the lever arm of
/// uniform-pressure Coulomb friction opposing a pure spin, M = μ N r̄.
double MeanRadiusOfRectangle(double a, double b);

}  // namespace ecpsim::evaluation
