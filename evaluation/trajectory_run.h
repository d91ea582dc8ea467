#pragma once
// Running one method on one scenario at one step size: the measured body's states at the
// scenario's sample times, its contact mode, penetration, energy, stop time and the CPU time of
// the steps.

#include <string>
#include <vector>

#include "engine/state.h"
#include "evaluation/method.h"
#include "evaluation/scenario.h"

namespace ecpsim::evaluation {

/// How a body touches the ground, from its pose: hull vertices within kModeSpread of the lowest
/// one, when that one is within kContactDistance of an obstacle.
enum class ContactMode { kNone = 0, kVertex = 1, kEdge = 2, kFace = 3 };
const char* ContactModeName(ContactMode mode);

/// m: soft-contact engines (MuJoCo, ODE, Bullet) rest a few tenths of a millimetre inside the
/// ground, so "touching" allows 1 mm either way.
constexpr double kContactDistance = 1e-3;
/// m: vertices this close in height to the lowest one touch with it (a tilt of 1e-4 rad over a
/// 1 m footprint); tighter than any modelled feature, looser than soft-contact sag differences.
constexpr double kModeSpread = 1e-4;
/// m/s: a body slower than this (|v| + length·|ω|) has stopped.
constexpr double kStopSpeed = 1e-3;

/// The contact mode of `body` at pose `state` against the scene's obstacles.
ContactMode ModeOfPose(const engine::Scene& scene, int body, const engine::BodyState& state);

struct RunRecord {
  std::vector<engine::BodyState> samples;  // Scenario::body at k · sample_interval, k = 0 … K
  std::vector<ContactMode> modes;          // at the same times
  std::vector<double> energies;            // J, ½mv² + ½ωᵀI_Wω − m g·p at the same times
  long steps = 0;
  bool failed = false;
  std::string failure;     // the exception's message when failed
  double cpu_seconds = 0;  // thread CPU time spent in Step() calls
  // m, deepest mesh vertex in an obstacle, or hull vertex of a body in the hull of a body it is
  // paired with, after any step
  double max_penetration = 0;
  double stop_time = -1;      // s, first step end after which the body stays below kStopSpeed
  double max_speed_late = 0;  // m/s, max |v| + length·|ω| over the last `late_window` seconds
  double drift_late = 0;      // m, |Δp| + length·|Δθ| over that window
  int iterations_max = 0;
  double iterations_mean = 0;
  // a push (Scenario::pusher ≥ 0): per step from kPushSettleTime after the first contact on,
  // the pusher's mean force on the measured body over the step along the push direction, N
  std::vector<double> push_forces;
  // m, Scenario::measure_drift: the largest projected CM displacement of a dynamic body from its
  // place at Scenario::drift_from after any later step (Scenario::drift_projection); −1 where
  // not measured
  double max_drift = -1;
};

/// Runs `method` on `scenario` with step h until scenario.scene.duration.
/// Stops early (failed, "CPU limit …") when the steps take more than `cpu_limit_s` CPU seconds,
/// within the step that reaches it for ecpsim's methods (CpuBudget; the state is then the last
/// step's). A
/// peer that cannot build its model of the scene (engine::SolverFailure from its adapter: MuJoCo's
/// data too large to allocate) is a failed run of no steps.
/// @throws InputError if h does not divide the sample interval (to 1e-9 relative), the scene with
///         step h fails engine::ValidateScene (MakeStepper), or an external engine cannot model
///         it.
RunRecord RunTrajectory(const Method& method, const Scenario& scenario, double h,
                        double cpu_limit_s = 300, double late_window = 0.5);

/// The contact modes and samples of the scenario's closed form, at its sample times.
RunRecord AnalyticTrajectory(const Scenario& scenario);

}  // namespace ecpsim::evaluation
