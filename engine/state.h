#pragma once
// The per-step data of a simulation (MuJoCo's mjData): poses, velocities, contact solutions.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/step_report.h"
#include "engine/warm_start.h"

namespace ecpsim::engine {

struct BodyState {
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();            // m, CM position
  Eigen::Quaterniond Q_WB = Eigen::Quaterniond::Identity();  // unit, body → world
  Eigen::Vector3d v_WB = Eigen::Vector3d::Zero();            // m/s
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();            // rad/s, world frame
};

/// The solution of one contact's part of the MNCP at the end of the last step.
struct ContactState {
  Eigen::Vector3d a1 = Eigen::Vector3d::Zero();  // m, ECP on the body's hull (world)
  Eigen::Vector3d a2 = Eigen::Vector3d::Zero();  // m, ECP on the obstacle (world)
  // N·s, N·s, N·s, N·m·s: the impulses over the whole step (summed over its sub-steps)
  double p_n = 0, p_t = 0, p_o = 0, p_r = 0;
  double sigma = 0;                              // m/s, slip magnitude multiplier
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  // contact frame: normal out of G ...
  Eigen::Vector3d t = Eigen::Vector3d::UnitX();  // ... and tangents
  Eigen::Vector3d o = Eigen::Vector3d::UnitY();
  WarmStart warm_start;  // the unknowns of the model that solved it last
};

/// The sleep rule's memory (engine/README.md, "Sleeping islands"; island_sleep.h): what decides
/// whether an island replays its last step, so it is state, and checkpoints carry it. Empty (or
/// of other sizes than the scene's) reads as every body awake.
struct RestRecord {
  // per body: consecutive steps its island ended at rest with its contacts and loads unchanged
  std::vector<std::int64_t> steps;
  // per body: the model that solved its island's last step that a model solved (what a replay
  // repeats, and what trajectory.csv's model column says of it)
  std::vector<StepModel> models;
  // per body: that step's residual (StepReport::residual's part of its island), which a replay
  // reports as its own: it commits the same solution
  std::vector<double> residuals;
  // per contact: whether it was in an island's step at the last step (kept with sleeping off
  // too); a contact that was not holds no impulse and no warm start, and the next step does not
  // read it unless it enters
  std::vector<char> in_step;
};

struct State {
  double t = 0;            // s: steps · h (AdvanceTime), never a sum of roundings
  std::int64_t steps = 0;  // steps taken since t = 0
  std::vector<BodyState> bodies;
  std::vector<ContactState> contacts;  // one per Scene::contacts entry
  RestRecord rest;
};

/// Whether a body's pose and velocities are all finite numbers.
bool IsFinite(const BodyState& body);

/// The body frame → world: rotation Q_WB, translation p_WB (the CM).
Eigen::Isometry3d PoseOf(const BodyState& body);

/// Counts a step of length h: t = steps · h, one rounding of an exact integer times h, so the
/// time carries no round-off accumulated over the run (scene_limits.h, kMaxSteps).
void AdvanceTime(double h, State& state);

/// The state at t = 0 from the bodies' initial conditions; contacts start without a warm start.
State InitialState(const Scene& scene);

}  // namespace ecpsim::engine
