#pragma once
// The hull model's island problem at the start of a step: its bodies, contacts and their scales,
// the hull windows, the pairs' normals and the energy an ejection may give (engine/README.md,
// "Islands", "Large hulls: the window", "Roots that gain energy").

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/contact_model.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine::hull {

/// The world point of `shape` at pose (c, R) farthest along the world `direction`.
Eigen::Vector3d WorldSupport(const geometry::ConvexShape& shape, const Eigen::Vector3d& c,
                             const Eigen::Matrix3d& R, const Eigen::Vector3d& direction);

/// The island's problem at the start of the step [t, t + h]: its bodies (StartOfStep), the
/// kinematic bodies its contacts touch (pose and prescribed twist over the step), its grippers
/// and its contacts, G's window all of a fixed obstacle's constraints (F's windows are chosen by
/// SelectWindows).
IslandProblem MakeHullProblem(const Scene& scene, const Island& island, double t, double h,
                              const IslandState& state);

/// Each body's scales (BodyScales), raised where contacts with moving bodies or a gripper's drive
/// bring more than its own motion shows (RaiseToGripperDrive, RaiseToIslandVelocity). False,
/// with `tried` saying why, where a body's free flight is not finite.
bool MakeIslandScales(const Scene& scene, const Island& island, const IslandProblem& problem,
                      const IslandState& state, IslandScales& scales,
                      std::vector<FailedAttempt>& tried);

/// Whether bodies touch bodies in the island (several bodies, or one against a kinematic body).
bool Coupled(const IslandProblem& problem);

/// A jaw moves as its gripper drives it: at the frame's velocity across the axis, turning with
/// it, and closing under the actuator's impulse, none of which its applied loads show. Raises
/// each jaw's velocity scale (and its impulse scale m V) to that drive.
void RaiseToGripperDrive(const IslandProblem& problem, IslandScales& scales);

/// A body's own velocity scale (its speed, or g h at rest) is far below what a contact with a
/// moving body brings it (a box at rest hit at 1.5 m/s measured its impulse in units 10⁴ ×
/// too small, and Newton diverged). In a coupled island each body's velocity scale is raised to
/// the largest of the island's and of the kinematic bodies' speeds over the bodies' lengths; its
/// impulse scale follows (m V). A body alone against obstacles keeps its own.
void RaiseToIslandVelocity(const IslandProblem& problem, IslandScales& scales);

/// In a coupled island every contact sticks up to kStickCreepFraction of its body's velocity
/// scale (hull_model.h); a body alone against obstacles keeps the paper's exact law.
void SetStickCreep(const IslandScales& scales, IslandProblem& problem);

/// The rotation of island body b at the end of the step if it kept its angular velocity.
Eigen::Matrix3d PredictedRotation(const IslandProblem& problem, int b);
/// The same for the G of contact `cp` that moves (a body or a kinematic body).
Eigen::Matrix3d PredictedOtherRotation(const IslandProblem& problem, const IslandContact& cp);

/// Whether `c` ended its step pressed onto one hull face alone: a normal impulse, and one face
/// multiplier above kDegenerateActiveFraction of the largest.
bool FlatOnOneFace(const ContactState& c);

/// Each contact's windows around the support features at the predicted poses: F's in the
/// direction of −n with `settings.window_rings` rings (one fewer for a body alone that ended
/// the last step flat on one face, one more for a fixed obstacle's contact without a warm
/// start), a moving G's in +n.
void SelectWindows(const SolverSettings& settings, const IslandState& state,
                   IslandProblem& problem);

/// F's and G's poses at the start of the step (contact `cp` with a moving G).
std::pair<Eigen::Isometry3d, Eigen::Isometry3d> StartPoses(const IslandProblem& problem,
                                                           const IslandContact& cp);

/// A pair's last normal orients its guesses and hull windows and is the axis of its ejection
/// allowance. A pair that did not push in the last step, whose normal leaves the start-of-step
/// hulls overlapping, takes the candidate axis that separates them the most (the separating axis
/// where one exists): from an overlapping axis Newton found roots that kicked a finger 4 mm
/// behind a box into touching. A pair that pushed keeps its solved normal (its warm start's
/// friction is in that frame). Writes per contact the hulls' overlap along its normal into
/// `overlaps` (m; 0 for a fixed G).
void SeparatePairs(const IslandProblem& problem, const IslandScales& scales, IslandState& state,
                   std::vector<double>& overlaps);

/// J: twice the kinetic energy of moving the bodies out of their deepest start-of-step
/// penetration of any G within one step, plus the applied impulses' work over that depth;
/// `overlaps` as SeparatePairs writes them.
double EjectionEnergy(const IslandProblem& problem, const IslandState& state,
                      const IslandScales& scales, const std::vector<double>& overlaps);

/// The multipliers of `from_window` (in `from` from `from_at` on) carried by face index to
/// `to_window` (in `to` from `to_at` on); a face new to `to_window` keeps its value.
void CarryByFace(const std::vector<int>& from_window, const Eigen::VectorXd& from, int from_at,
                 const std::vector<int>& to_window, Eigen::VectorXd& to, int to_at);

/// `z` of `from` (laid out as `from_layout`) moved to `to`'s layout: the same unknowns,
/// multipliers matched by face index (0 for a face new to a window).
Eigen::VectorXd RemapWindows(const IslandProblem& from, const IslandLayout& from_layout,
                             const Eigen::VectorXd& z, const IslandProblem& to,
                             const IslandLayout& to_layout);

}  // namespace ecpsim::engine::hull
