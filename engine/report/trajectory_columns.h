#pragma once
// The columns of a trajectory (trajectory.csv, the Python module's run()): one row of numbers
// per state, named once here so every output names them alike.

#include <string>
#include <vector>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// The column names:
/// - `t`;
/// - per body (prefixed `<body>.` when there are several bodies)
///   `px py pz qw qx qy qz vx vy vz wx wy wz`;
/// - per contact group (ContactGroups: the contacts of one body with one obstacle or other body,
///   combined by CombinedContact where it touches with several parts; prefixed `<F>.<G>.` —
///   body, then obstacle or other body — when there are several groups)
///   `a1x a1y a1z a2x a2y a2z pn pt po pr sigma fn ft fo fr`: the ECPs, the impulses over the
///   step (N·s, N·s, N·s, N·m·s), the slip multiplier (m/s) and the average contact forces over
///   the step, impulse / h (N, N, N, N·m);
/// - per kinematic body K, what a force/torque sensor on it reads (WrenchOnOther): for each body
///   F touching it `<K>.<F>.fx fy fz mx my mz` (its contacts' sum) and their sum `<K>.fx fy fz mx
///   my mz`, in N and N·m, world axes, moments about K's reference point;
/// - per gripper G `<G>.width` (m: its jaws' centres apart along its closing axis) and
///   `<G>.force` (N: the closing force of the step that ended at the row; the initial row: the
///   first step's);
/// - `iters residual`.
std::vector<std::string> TrajectoryColumns(const Scene& scene);

/// The text columns that follow TrajectoryColumns: per body `model` (prefixed `<body>.` when
/// there are several bodies), what solved its step — StepModelName: `free`, `planar`, `hull`,
/// `multipatch`, `point`, `kinematic` — or `initial` in the row of the initial state.
std::vector<std::string> TrajectoryModelColumns(const Scene& scene);

/// The row's text values, in TrajectoryModelColumns' order.
std::vector<std::string> TrajectoryModels(const Scene& scene, const StepReport& report);

/// Whether `column` is one of TrajectoryModelColumns' names (text, not a number).
bool IsModelColumn(const std::string& column);

/// The row of `state` after a step that reported `report`, in TrajectoryColumns' order (the
/// initial state's row has zero impulses, forces and iterations). Values may be non-finite if
/// the state is; callers check.
std::vector<double> TrajectoryValues(const Scene& scene, const State& state,
                                     const StepReport& report);

}  // namespace ecpsim::engine
