#pragma once
// One contact's rows of the MNCP and their analytic Jacobian, for a G that is fixed, kinematic or
// another body of the island: the paper's contact constraints (eqs. re_contact_multiple_1…5, the
// scale fixed on G's side), its friction (eq. friction) and the contact impulse in the
// Newton–Euler rows (eq. discrete_NE). Each equation is one function below, which sets its own
// rows of F and J and no others; AddContactRows calls them all. engine/README.md writes the rows
// out ("The MNCP", "Islands").

#include <vector>

#include <Eigen/Core>

#include "engine/mncp/body_step.h"
#include "engine/mncp/contact_frame.h"
#include "engine/mncp/mncp_layout.h"
#include "engine/scene.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

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

/// Sets contact L's rows and, if `J` is not null, their Jacobian, and adds the contact's impulse
/// to the Newton–Euler rows of F (`body`) and, when G is a dynamic body (`other` with a column),
/// the opposite impulse to G's: the equations of EvaluateIslandMncp (island_mncp.h). `other` is
/// G's motion (fixed G: null, then these are EvaluateMncp's rows). The rows of F and J that the
/// contact owns are set, the Newton–Euler rows added to; J, when given, is zero in the contact's
/// own rows.
void AddContactRows(const ContactSides& sides, const MncpLayout::Contact& L, const StepMotion& body,
                    const StepMotion* other, double h, const Eigen::VectorXd& z, Eigen::VectorXd& F,
                    Eigen::MatrixXd* J);

/// Sets contact L's friction rows (paper eq. friction: the Fritz–John conditions of maximum
/// dissipation on the ellipsoid) for the sliding velocity (v_t, v_o), the spin v_r, the friction
/// impulses (p_t, p_o, p_r) and `slip`, the multiplier σ (σ + ε for a creeping contact):
///   F[p_t] = e_t² μ p_n v_t + p_t slip,  F[p_o] = e_o² μ p_n v_o + p_o slip,
///   F[p_r] = e_r² μ p_n v_r + p_r slip,  F[σ] = μ p_n − ‖(p_t/e_t, p_o/e_o, p_r/e_r)‖.
/// Returns that norm, ‖p̂‖, for the Jacobian.
double SetFrictionRows(const Friction& fr, double p_n, double v_t, double v_o, double v_r,
                       double p_t, double p_o, double p_r, double slip,
                       const MncpLayout::Contact& L, Eigen::VectorXd& F);

/// N = Σ_j l_G,j ∇g_j of contact L at z in world coordinates (|N| ≈ 1 at a solution), G at
/// `other`'s end pose (null: fixed); the contact frame is MakeContactFrame(N, …).
Eigen::Vector3d ContactNormalCombination(const ContactSides& sides, const MncpLayout::Contact& L,
                                         const StepMotion* other, const Eigen::VectorXd& z);

// --- AddContactRows in parts: the contact at z, then one function per equation ---

/// G's side of a contact at a2: its window's world gradients, N = Σ_j l_G,j ∇g_j and the
/// derivatives of N (a fixed G in world coordinates; a moving one in its frame at its end pose).
/// On a plane (L.on_plane()) l_G = 1 and N is the plane's constant gradient, without derivatives.
class OtherSide {
 public:
  /// `motion`: G's (null: fixed); the derivatives only `with_derivatives`.
  OtherSide(const ContactSides& sides, const MncpLayout::Contact& L, const Eigen::VectorXd& z,
            const StepMotion* motion, double h, bool with_derivatives);

  // constraint j of the window at a2: g_j, its gradient in G's frame and in the world, and the
  // world gradient's derivative in a2
  double Value(int j) const { return sides_.other->Value(Constraint(j), y_); }
  Eigen::Vector3d FrameGradient(int j) const { return sides_.other->Gradient(Constraint(j), y_); }
  Eigen::Vector3d Gradient(int j) const {
    const Eigen::Vector3d gradient = FrameGradient(j);
    return motion_ ? Eigen::Vector3d(motion_->end.R * gradient) : gradient;
  }
  Eigen::Matrix3d Hessian(int j) const {
    const Eigen::Matrix3d H = sides_.other->Hessian(Constraint(j), y_);
    return motion_ ? Eigen::Matrix3d(motion_->end.R * H * motion_->end.R.transpose()) : H;
  }

  const Eigen::Vector3d& N() const { return N_; }
  double l_g_sum() const { return l_g_sum_; }
  const Eigen::Matrix3d& dN_da2() const { return dN_da2_; }
  const Eigen::Matrix3d& dN_dv() const { return dN_dv_; }  // in G's v⁺ (a dynamic G)
  const Eigen::Matrix3d& dN_dw() const { return dN_dw_; }  // in G's ω⁺ (a dynamic G)
  const Eigen::Matrix3d& dy_dw() const { return dy_dw_; }  // y_G in G's ω⁺ (a dynamic G)

 private:
  int Constraint(int j) const { return sides_.other_window ? (*sides_.other_window)[j] : j; }

  const ContactSides& sides_;
  const StepMotion* motion_;  // null: fixed, world frame
  Eigen::Vector3d y_;
  Eigen::Vector3d N_ = Eigen::Vector3d::Zero();
  double l_g_sum_ = 0;
  Eigen::Matrix3d dN_da2_ = Eigen::Matrix3d::Zero(), dN_dv_ = Eigen::Matrix3d::Zero(),
                  dN_dw_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d dy_dw_ = Eigen::Matrix3d::Zero();
};

/// One contact at z, as its equations see it: the unknowns, G's side, the contact frame, the
/// lever arms at the end of the step and the velocity at the ECP relative to G. Holds references
/// to its arguments, which must outlive it.
struct ContactAtZ {
  /// ECPSIM_DEMAND: a contact on a plane has a fixed G (`other` null).
  ContactAtZ(const ContactSides& sides, const MncpLayout::Contact& L, const StepMotion& body,
             const StepMotion* other, double h, const Eigen::VectorXd& z, bool with_jacobian);

  const ContactSides& sides;
  const MncpLayout::Contact& L;
  const StepMotion& body;   // F's motion
  const StepMotion* other;  // G's motion, null for a fixed G
  double h;                 // s
  const Eigen::VectorXd& z;
  bool plane;          // on a plane: a2, s and l_G left out, N constant (MncpLayout)
  bool dynamic_other;  // G's ν⁺ are unknowns
  OtherSide G;

  Eigen::Vector3d a1, a2;  // m, world
  double s;                // the gap along N
  double p_n, p_t, p_o, p_r, sigma;
  ContactFrame frame;          // (n, t, o) from N
  Eigen::Vector3d r;           // a1 − c_F⁺
  Eigen::Vector3d r_other;     // a2 − c_G⁺ (zero for a fixed G)
  Eigen::Vector3d y;           // a1 in F's body frame at its end pose, R_F⁺ᵀ r
  Eigen::Vector3d force;       // n p_n + t p_t + o p_o, on F at a1
  Eigen::Vector3d v_contact;   // (v_F⁺ + ω_F⁺ × r) − (v_G + ω_G × r_G)
  Eigen::Vector3d w_relative;  // ω_F⁺ − ω_G
  double v_t, v_o, v_r;        // t · v_contact, o · v_contact, n · w_relative
  double slip;                 // σ, or σ + ε for a creeping contact

  // with the Jacobian only
  FrameDerivatives d;      // of (n, t, o) in N; zero on a plane
  Eigen::Matrix3d dy_da1;  // R_F⁺ᵀ
  Eigen::Matrix3d dy_dw;   // h [y]× R_Fᵀ J_l(−hω_F⁺)

  /// The rows of the normal-cone equation: a2's, or a1's on a plane.
  int ConeRow() const { return plane ? L.a1 : L.a2; }
};

// Each function sets the rows of F named and, if `J` is not null, the same rows of J (zero in
// those rows on entry); the Newton–Euler rows are added to.

/// eq. discrete_NE, the contact's terms: F's rows −(force, r × force + n p_r), a dynamic G's
/// +(force, r_G × force + n p_r).
void AddContactImpulse(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// eq. re_contact_multiple_1, normalized on G's side: a1 − a2 − s N = 0 (rows a1; none on a
/// plane, where a2 = a1 − s N defines a2).
void SetSeparationRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// eq. re_contact_multiple_2, normalized on G's side: N + Σ_i l_i R_F⁺ ∇f_i(y) = 0 (rows
/// ConeRow()).
void SetNormalConeRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// eq. re_contact_multiple_3: 0 ≤ l_i ⊥ −f_i(y) ≥ 0, F's hull at its end pose (rows l).
void SetHullConstraintRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// eq. re_contact_multiple_4, 0 ≤ l_G,j ⊥ −g_j(y_G) ≥ 0 (rows l_G), and the scale of the
/// multipliers, Σ_j l_G,j − 1 = 0 (row s) — the engine's normalization in place of the paper's
/// l_k = 1 (engine/README.md, "The active facet k"). None on a plane.
void SetObstacleConstraintRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// eq. re_contact_multiple_5 with a smooth gap: 0 ≤ p_n ⊥ s ≥ 0 (row p_n; on a plane
/// s = g(a1)/|N|²).
void SetGapRow(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// eq. friction on the velocity relative to G at the ECP: SetFrictionRows's rows p_t, p_o, p_r
/// and σ, with their Jacobian.
void SetMaximumDissipationRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J);

}  // namespace ecpsim::engine
