#pragma once
// The mixed nonlinear complementarity problem of one body for one time step: the residual of the
// paper's "Summary of the discrete-time dynamic model" and its analytic Jacobian. Its parts are
// the body's step (body_step.h), the contact frame (contact_frame.h), the unknowns' layout
// (mncp_layout.h) and the convergence measure (mncp_measure.h); the equations, unknowns and the
// handling of the active facet are written out in engine/README.md. Its per-body and per-contact
// rows (the end of this file) also build the MNCP of an island of bodies in contact with each
// other (island_mncp.h).

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/mncp/body_step.h"
#include "engine/mncp/contact_frame.h"
#include "engine/mncp/mncp_layout.h"
#include "engine/mncp/mncp_measure.h"
#include "engine/scene.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// Residual F(z) in physical units (rows as in MncpLayout). The friction cone row is written as
/// μ p_n − ‖(p_t/e_t, p_o/e_o, p_r/e_r)‖ instead of the paper's ζ = (μ p_n)² − ‖…‖²: for p_n ≥ 0
/// both have the same sign and the same zeros, so 0 ≤ σ ⊥ · ≥ 0 has the same solutions, but ζ has
/// a double root at p̂ = 0 (free flight: ζ = −‖p̂‖²), where Newton converges only linearly and
/// an error ε in p̂ shows in ζ as ε²; the norm form converges in one step there.
/// If `J` is not null also the analytic
/// Jacobian ∂F/∂z, including the dependence of the hull geometry on q⁺ = q + h G(q) ν⁺.
/// With `jacobian_is_zero` the caller promises J is already layout.size square and zero (as
/// SolveMcp hands it to its callback), and J is not cleared again.
void EvaluateMncp(const BodyProblem& problem, const MncpLayout& layout, const Eigen::VectorXd& z,
                  Eigen::VectorXd* F, Eigen::MatrixXd* J, bool jacobian_is_zero = false);

// --- the building blocks of EvaluateMncp, shared with the island MNCP (island_mncp.h) ---

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

/// Sets the contact-free Newton–Euler rows of `problem`'s body, whose ν⁺ is z[column … +5]: F's
/// six rows and, if `J` is not null, its two diagonal 3 × 3 blocks (F and J already sized and
/// zeroed). Returns the body's motion (the derivatives only with J).
StepMotion AddBodyRows(const BodyProblem& problem, int column, const Eigen::VectorXd& z,
                       Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// What one contact joins: F's hull (body frame) and window, G's shape (world frame when G is
/// fixed, else its own frame) and window — null: all of G's constraints, in order — and the
/// friction between them. The pointers must outlive the call.
struct ContactSides {
  const geometry::ConvexShape* hull;
  const std::vector<int>* window;
  const geometry::ConvexShape* other;
  const std::vector<int>* other_window;
  Friction friction;
  Eigen::Vector3d tangent_reference;  // world, fixed during the step
  double stick_creep = 0;             // m/s, IslandContact::stick_creep (0: exact sticking)
};

/// Sets contact L's friction rows (paper eq. friction: the Fritz–John conditions of maximum
/// dissipation on the ellipsoid) for the sliding velocity (v_t, v_o), the spin v_r, the friction
/// impulses (p_t, p_o, p_r) and `slip`, the multiplier σ (σ + ε for a creeping contact):
///   F[p_t] = e_t² μ p_n v_t + p_t slip,  F[p_o] = e_o² μ p_n v_o + p_o slip,
///   F[p_r] = e_r² μ p_n v_r + p_r slip,  F[σ] = μ p_n − ‖(p_t/e_t, p_o/e_o, p_r/e_r)‖.
/// Returns that norm, ‖p̂‖, for the Jacobian.
double SetFrictionRows(const Friction& fr, double p_n, double v_t, double v_o, double v_r,
                       double p_t, double p_o, double p_r, double slip,
                       const MncpLayout::Contact& L, Eigen::VectorXd& F);

/// Sets contact L's rows and, if `J` is not null, their Jacobian, and adds the contact's wrench
/// to the Newton–Euler rows of F (`body`) and, when G is a dynamic body (`other` with a column),
/// the opposite wrench to G's: the equations of EvaluateIslandMncp (island_mncp.h). `other` is G's
/// motion (fixed G: null, then these are EvaluateMncp's rows to the bit).
void AddContactRows(const ContactSides& sides, const MncpLayout::Contact& L, const StepMotion& body,
                    const StepMotion* other, double h, const Eigen::VectorXd& z, Eigen::VectorXd& F,
                    Eigen::MatrixXd* J);

/// N = Σ_j l_G,j ∇g_j of contact L at z in world coordinates (|N| ≈ 1 at a solution), G at
/// `other`'s end pose (null: fixed); the contact frame is MakeContactFrame(N, …).
Eigen::Vector3d ContactNormalCombination(const ContactSides& sides, const MncpLayout::Contact& L,
                                         const StepMotion* other, const Eigen::VectorXd& z);

}  // namespace ecpsim::engine
