#pragma once
// How far a scene turned about z moves from its turned motion: the scene and its turned copy
// (tests/engine/turned_scene.h) stepped side by side, the copy's poses turned back and compared
// with the original's after every step. Shared by the Turned tests and ecpsim_rotation_check.

#include <string>
#include <vector>

#include "engine/scene.h"

namespace ecpsim::engine::testing {

/// The largest differences over every body (dynamic, jaws and kinematic) and every step.
struct TurnedDeviation {
  double position = 0;  // m: the largest |p − R⁻¹ p'| of a CM, p the original's, p' the turned's
  double angle = 0;     // rad: the largest angle of the turn from Q to R⁻¹ Q'
  // m: the largest angle × that body's radius (its farthest mesh vertex from the CM), what the
  // orientation's difference moves the body's surface by
  double surface = 0;
  std::string body;  // where `position` is largest: the body's name ...
  double time = 0;   // ... and the time, s
  int steps = 0;     // the steps compared
};

/// Steps `scene` and TurnedAboutZ(scene, angle) (rad) for `steps` steps each, each under the
/// scene's own model and settings, and measures their differences after every step.
/// @throws SolverFailure or ModelInvalid as Step does, for either run.
TurnedDeviation MeasureTurnedDeviation(const Scene& scene, double angle, int steps);

/// Whether the rotation check applies to a scene: more than one body (dynamic or kinematic) or
/// a gripper, the scope (statically indeterminate contact needs two bodies or more).
bool IsMultiBody(const Scene& scene);

/// The steps the check runs for a scene: its whole duration, duration / h.
int RotationCheckSteps(const Scene& scene);

/// The shipped multi-body scenes (file names in `scenes_dir`, sorted).
std::vector<std::string> MultiBodyScenes(const std::string& scenes_dir);

}  // namespace ecpsim::engine::testing
