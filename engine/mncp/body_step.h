#pragma once
// One body's step without its contacts' rows: what its MNCP needs from the start of the step
// (inertia, loads, the free-flight velocities with the implicit gyroscopic impulse), its pose at
// the end of the step, its contact-free Newton–Euler rows with the gyroscopic term, and the
// energy a step adds (engine/README.md).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// One contact of the body: its hull (body frame) against a fixed convex obstacle (world frame).
struct ContactProblem {
  const geometry::ConvexShape* hull = nullptr;      // body frame, origin at the CM
  const geometry::ConvexShape* obstacle = nullptr;  // world frame
  std::vector<int> window;  // hull constraints that enter the MNCP (all, or a window)
  Friction friction;
  Eigen::Vector3d tangent_reference = Eigen::Vector3d::UnitX();  // fixed during the step
};

/// Velocities at the end of the step if no contact acts (see StartOfStep).
struct FreeFlight {
  Eigen::Vector3d v, w;
};

/// Everything one body's MNCP needs from the start of the step.
struct BodyProblem {
  double h = 0.01;                    // s
  double mass = 1;                    // kg
  Eigen::Matrix3d inertia_world;      // kg·m², R I_B Rᵀ at the start of the step
  Eigen::Vector3d c, v, w;            // CM position, velocity, spatial angular velocity
  Eigen::Matrix3d R;                  // body → world at the start of the step
  Eigen::Matrix<double, 6, 1> p_ext;  // N·s, N·m·s: gravity + applied loads over the step
  Eigen::Vector3d p_gravity = Eigen::Vector3d::Zero();  // N·s: gravity's part of p_ext, h m g
  // the step's velocities without contact: m (v⁺ − v) = p_ext,f and
  // I_w (ω⁺ − ω) + h ω⁺ × I_w ω⁺ = p_ext,τ (solved once here: every guess starts from it)
  FreeFlight free;
  std::vector<ContactProblem> contacts;
};

/// The body part of a BodyProblem (no contacts yet) for body `body` of `scene` at `state`, for the
/// step [t, t + h]: world inertia, gravity and applied loads at the start of the step
/// (FORMULATION.md trap 4), and the free-flight velocities with the implicit gyroscopic impulse
/// (engine/README.md).
BodyProblem StartOfStep(const Scene& scene, int body, const BodyState& state, double t, double h);

/// Whether the step's free-flight velocities and end pose are finite: a state that already spins
/// at an overflowing rate (or a load that is not finite) cannot be stepped; then appends the
/// free flight's failure (its |ω|) to `tried`.
bool FreeFlightIsFinite(const BodyProblem& problem, std::vector<FailedAttempt>& tried);

/// Position and orientation at the end of the step for velocities (v⁺, ω⁺).
struct EndPose {
  Eigen::Vector3d c;  // c + h v⁺
  Eigen::Matrix3d R;  // Exp(h ω⁺) R
};
EndPose PoseAfterStep(const BodyProblem& problem, const Eigen::Vector3d& v,
                      const Eigen::Vector3d& w);
/// The same for a pose (c, R) at the start of a step of `h` seconds (a kinematic body's).
EndPose PoseAfterStep(const Eigen::Vector3d& c, const Eigen::Matrix3d& R, double h,
                      const Eigen::Vector3d& v, const Eigen::Vector3d& w);

/// The angular Newton–Euler row without contact, I_w (ω⁺ − ω) + h ω⁺ × I_w ω⁺ (the implicit
/// gyroscopic impulse, engine/README.md; N·m·s), and its derivative in ω⁺ (kg·m²).
Eigen::Vector3d GyroscopicResidual(const BodyProblem& problem, const Eigen::Vector3d& w);
Eigen::Matrix3d GyroscopicJacobian(const BodyProblem& problem, const Eigen::Vector3d& w);

/// A body's motion over the step as a contact's rows see it: its end pose and velocities and,
/// when the velocities are unknowns, their index in z and the derivatives of the end pose in ω⁺.
struct StepMotion {
  EndPose end;
  Eigen::Vector3d v, w;  // m/s, rad/s (world): ν⁺, or a kinematic body's prescribed twist
  int column = -1;       // z index of v⁺ (ω⁺ at + 3); −1: prescribed, no unknowns
  // J_l(hω⁺): ∂(R⁺ x_B)/∂ω⁺ = −h [R⁺ x_B]× J_l(hω⁺)
  Eigen::Matrix3d Jl_plus = Eigen::Matrix3d::Zero();
  // Rᵀ J_l(−hω⁺): ∂y/∂ω⁺ = h [y]× Rᵀ J_l(−hω⁺) for y = R⁺ᵀ(x − c⁺)
  Eigen::Matrix3d Rt_Jl_minus = Eigen::Matrix3d::Zero();
};

/// Sets the contact-free Newton–Euler rows (paper eq. discrete_NE without the contact impulses,
/// which AddContactImpulse adds) of `problem`'s body, whose ν⁺ is z[column … +5]: F's six rows
///   m (v⁺ − v) − p_ext,f,   I_w (ω⁺ − ω) + h ω⁺ × I_w ω⁺ − p_ext,τ
/// and, if `J` is not null, its two diagonal 3 × 3 blocks (F and J already sized and zeroed).
/// Returns the body's motion (the derivatives only with J).
StepMotion AddBodyRows(const BodyProblem& problem, int column, const Eigen::VectorXd& z,
                       Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// J: the body's energy (kinetic and gravitational, −m g·c) at the end of the step minus at its
/// start, minus the work of the applied loads over the mean velocity — what the contact
/// impulses added. The potential changes by −h m g·v⁺ (the step moves c by h v⁺). Free flight has
/// it ≤ 0 (the implicit step dissipates −½ m |g h|² and, by the implicit gyroscopic term,
/// rotational energy); a contact only takes energy away.
double StepEnergyGain(const BodyProblem& problem, const Eigen::Vector3d& v,
                      const Eigen::Vector3d& w);

}  // namespace ecpsim::engine
