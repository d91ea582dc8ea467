#pragma once
// The mixed nonlinear complementarity problem of one body for one time step: its unknowns, the
// residual of the paper's "Summary of the discrete-time dynamic model" and its analytic Jacobian.
// The equations, unknowns and the handling of the active facet are written out in engine/README.md.
// Its per-body and per-contact building blocks (the end of this file) also build the MNCP of an
// island of bodies in contact with each other (island_mncp.h).

#include <array>
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

/// Where each unknown of the MNCP lives in z. Free (equality) unknowns come first: ν⁺ and per
/// contact (a1, a2, s, p_t, p_o, p_r); then the complementarity unknowns: per contact the hull
/// multipliers l (one per window constraint), the obstacle multipliers l_G, p_n and σ. Row i of
/// the residual is paired with unknown i.
///
/// A contact on a plane (G a fixed half-space, engine/README.md "Contacts on a plane") has no
/// a2, s and l_G: with one linear constraint l_G = 1, N is the plane's normal, s = g(a1)/|N|²
/// and a2 = a1 − s N, so the layout leaves them out (a2 = s = −1, l_g_count = 0) and the
/// cone rows pair with a1: 20 unknowns instead of 25 for a body on the ground.
struct MncpLayout {
  struct Contact {
    int a1, a2, s, p_t, p_o, p_r;  // free (a2, s: −1 on a plane)
    int l, l_count;                // hull multipliers
    int l_g, l_g_count;            // obstacle multipliers (none on a plane)
    int p_n, sigma;
    bool on_plane() const { return s < 0; }
  };
  int num_free = 0;
  int size = 0;
  std::vector<Contact> contacts;
};

MncpLayout MakeLayout(const BodyProblem& problem);

/// The contact blocks of a layout whose first `first` unknowns are ν⁺ of one or more bodies:
/// per contact k its free block (a1, a2, s, p_t, p_o, p_r) from `first` on, then the
/// complementarity blocks with counts[k] = {l_count, l_g_count}; l_g_count = 0 lays out a
/// contact on a plane (free block a1, p_t, p_o, p_r). MakeLayout is LayOutContacts(6, …) with
/// every contact in the general form; island_mncp.h's MakeIslandLayout lays out several bodies
/// with it, and contacts on a plane in the plane form.
MncpLayout LayOutContacts(int first, const std::vector<std::array<int, 2>>& counts);

/// Contact L's point on G and gap at z: z's a2 and s, or on a plane (`plane` the half-space)
/// a1's projection onto it and its signed distance g(a1)/|∇g|².
struct ContactGap {
  Eigen::Vector3d a2;  // m
  double s;            // m per unit of |N|
};
ContactGap ContactGapAt(const MncpLayout::Contact& L, const geometry::ConvexShape* plane,
                        const Eigen::VectorXd& z);

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

/// J: the body's energy (kinetic and gravitational, −m g·c) at the end of the step minus at its
/// start, minus the work of the applied loads over the mean velocity — what the contact
/// impulses added. The potential changes by −h m g·v⁺ (the step moves c by h v⁺). Free flight has
/// it ≤ 0 (the implicit step dissipates −½ m |g h|² and, by the implicit gyroscopic term,
/// rotational energy); a contact only takes energy away.
double StepEnergyGain(const BodyProblem& problem, const Eigen::Vector3d& v,
                      const Eigen::Vector3d& w);

/// The contact frame (n, t, o) from the obstacle's normal-cone combination N = Σ l_G ∇g.
struct ContactFrame {
  Eigen::Vector3d n, t, o;
};
ContactFrame MakeContactFrame(const Eigen::Vector3d& N, const Eigen::Vector3d& tangent_reference);

/// Derivatives of MakeContactFrame(N, e)'s axes with respect to N (1/m where N is a gradient).
struct FrameDerivatives {
  Eigen::Matrix3d dn_dN, dt_dN, do_dN;
};
FrameDerivatives ContactFrameDerivatives(const Eigen::Vector3d& N, const ContactFrame& frame,
                                         const Eigen::Vector3d& e);

/// What the convergence measure measures lengths against (see MncpResidual).
struct ResidualUnits {
  double length;       // m: the body's length L (radius of gyration)
  double tolerance;    // the solver's tolerance on the measure (dimensionless)
  double coordinates;  // m: the largest |coordinate| of the body's centre of mass
};

/// Rows computed from world coordinates (y = R⁺ᵀ(a1 − c⁺) and the like: a rotation, two
/// differences, then the Newton solve's own error) are not asked to be more precise than this
/// many ulps of the largest coordinate involved — the ECPs' and the centre of mass's;
/// 1.4e-14 m on a body 1 m from the origin.
inline constexpr double kCoordinateRoundOffUlps = 64;

/// The MNCP's convergence measure: McpResidual of the scaled problem (each row in its body's own
/// unit, `row_scale` and `var_scale` from mncp_scaling.h), so it is dimensionless and means the
/// same for a millimetre and a kilometre body. Rows computed from world coordinates (a1 − a2 −
/// sN, the hull and obstacle constraints, the gap s, the moment r × p and the slip ω × r, with
/// r = a1 − c⁺) carry round-off of ≈ kCoordinateRoundOffUlps · ε · |x|, so a length below that
/// divided by the tolerance is not resolved: for a body far from the origin the measure is
/// relative to its coordinates instead of its length L. (The gap's tolerance, tolerance × L,
/// is a velocity error tolerance × L / h: negligible at any step a scene needs — 2e-8 m/s on a
/// 0.2 m body at h = 1e-5 s — but at h = 1e-10 s a sliding box's contact chatters by it.)
double MncpResidual(const MncpLayout& layout, const Eigen::VectorXd& z, const Eigen::VectorXd& F,
                    const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale,
                    const ResidualUnits& units);

/// MncpResidual's parts, shared with the island measure (island_mncp.h): the largest scaled row
/// error seen so far over rows added one at a time (an equation row i < num_free counts
/// |F̃_i| / divisor, a complementarity row |min(z̃_i, F̃_i / divisor)|; non-finite: ∞).
class ScaledRowResidual {
 public:
  /// The vectors are referenced, not copied: they must outlive this object.
  ScaledRowResidual(int num_free, const Eigen::VectorXd& z, const Eigen::VectorXd& F,
                    const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale);
  void AddRow(int i, double divisor);
  /// The rows of one contact block, those that carry world-coordinate round-off (see
  /// MncpResidual) divided by `factor` ≥ 1.
  void AddContact(const MncpLayout::Contact& L, double factor);
  double value() const { return value_; }

 private:
  int num_free_;
  const Eigen::VectorXd& z_;
  const Eigen::VectorXd& F_;
  const Eigen::VectorXd& row_scale_;
  const Eigen::VectorXd& var_scale_;
  double value_ = 0;
};

/// m: the length below which a contact's rows in metres are not resolved (MncpResidual): the
/// tolerance's share of kCoordinateRoundOffUlps ulps of the largest of |a1|, |a2|, |s| and
/// `coordinates` (the largest |coordinate| of the centres of mass involved).
double ContactRoundOffLength(const MncpLayout::Contact& L, const Eigen::VectorXd& z,
                             double coordinates, double tolerance);

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
