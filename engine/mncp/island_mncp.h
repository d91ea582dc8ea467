#pragma once
// The MNCP of a contact island for one time step: several bodies whose contacts couple them,
// solved as one problem (FORMULATION.md, "Two moving bodies"). Each contact joins the hull of a
// dynamic body F to a convex G that is fixed (an obstacle, world frame), kinematic (its motion
// over the step prescribed) or another dynamic body of the island. The equations are those of
// mncp_system.h with G at its own end-of-step pose; engine/README.md ("Islands: contacts between
// moving bodies") writes them out.
//
// An island of one body whose contacts are all fixed is the one-body MNCP to the bit: layout, F,
// J, measure and energy equal MakeLayout, EvaluateMncp, MncpResidual and StepEnergyGain exactly
// (both are built from the same parts — LayOutContacts, the one assembly AssembleMncp
// (mncp_assembly.h), ScaledRowResidual — and do the same floating-point operations in the same
// order; tests/engine/mncp/island_mncp_test.cpp).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "engine/mncp/contact_rows.h"
#include "engine/mncp/island_gripper.h"
#include "engine/mncp/mncp_system.h"
#include "engine/scene.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// A body whose motion over the step is prescribed (a conveyor, a turntable, a driven gripper):
/// no unknowns and no Newton–Euler rows; its end pose is PoseAfterStep(c, R, h, v, w), as a
/// dynamic body's. A fixed obstacle is the special case v = ω = 0 at the identity pose, but is
/// given as IslandContact::Other::kFixed (world-frame shape, no pose), as today.
struct KinematicBody {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();      // m, origin of its shape's frame at the start
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // shape frame → world at the start
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // m/s, velocity of c over the step (world)
  Eigen::Vector3d w = Eigen::Vector3d::Zero();      // rad/s, spatial angular velocity (world)
};

/// One contact of the island: the hull of dynamic body `body` (the F side; its ECP a1 and the
/// wrench (n p_n + t p_t + o p_o at a1, n p_r)) against G (ECP a2, the opposite wrench when G
/// is a dynamic body). Pick F and G once per pair and keep them: warm starts and outputs depend
/// on the order (FORMULATION.md).
struct IslandContact {
  enum class Other {
    kFixed,      // G is a fixed obstacle: `other_shape` in the world frame, `other` unused
    kKinematic,  // G is problem.kinematic[other]: `other_shape` in its frame
    kBody,       // G is island body `other` ≠ `body`: `other_shape` in its body frame
  };
  int body = 0;  // island index of F
  Other other_kind = Other::kFixed;
  int other = -1;                               // see Other
  // F's hull or the part of it the contact touches with, body frame (origin at the CM)
  const geometry::ConvexShape* hull = nullptr;
  std::vector<int> window;                      // F's constraints in the MNCP
  const geometry::ConvexShape* other_shape = nullptr;
  // G's constraints in the MNCP; for a fixed G all of them in order 0 … n−1 is today's MNCP. A
  // window that leaves some out is exact only if those hold at the solution (the caller checks,
  // as the hull window check does for F)
  std::vector<int> other_window;
  Friction friction;
  Eigen::Vector3d tangent_reference = Eigen::Vector3d::UnitX();  // world, fixed during the step
  // m/s, ε ≥ 0: the friction rows take σ + ε for σ, so a sticking contact creeps at a speed
  // ≤ ε (its friction −e² μ p_n v / ε is a stiff viscous law) and its friction is unique where
  // exact sticking leaves it statically indeterminate (a box pressed by a pusher onto the
  // ground: how much of the weight the pusher's friction carries). 0 is the paper's law exactly
  double stick_creep = 0;
};

/// The sides of contact `cp` as its rows see them (contact_rows.h).
ContactSides SidesOf(const IslandContact& cp);

/// Everything an island's MNCP needs from the start of the step.
struct IslandProblem {
  double h = 0.01;                       // s; every body's BodyProblem::h equals it
  std::vector<BodyProblem> bodies;       // per island body; their `contacts` stay empty
  std::vector<KinematicBody> kinematic;  // referenced by contacts of kind kKinematic
  std::vector<IslandContact> contacts;
  // grippers whose two jaws are island bodies: their Newton–Euler rows are the gripper's
  // (island_gripper.h)
  std::vector<IslandGripper> grippers;
};

/// Where each unknown of the island's MNCP lives in z: first ν⁺ = (v⁺, ω⁺) of every body (6
/// each, body b at Velocity(b)), then per contact (a1, a2, s, p_t, p_o, p_r), then per contact
/// the complementarity unknowns (l over F's window, l_G over G's window, p_n, σ). Row i of the
/// residual is paired with unknown i. For one body this is MncpLayout's order, but a contact on
/// a fixed half-space is laid out in the plane form (MncpLayout: no a2, s, l_G).
///
/// The Jacobian is block-sparse: body b's Newton–Euler rows touch only ν_b⁺ and the contact
/// blocks of b's contacts, and a contact's rows only its own block and the ν⁺ of its one or two
/// dynamic bodies — per-body 6 × 6 blocks coupled only through shared contacts. It is returned
/// dense (EvaluateIslandMncp) or sparse (EvaluateIslandMncpSparse) with that pattern.
struct IslandLayout {
  int num_bodies = 0;
  int num_free = 0;
  int size = 0;
  std::vector<MncpLayout::Contact> contacts;
  /// z index of v⁺ of island body `body` (ω⁺ follows at + 3).
  static int Velocity(int body) { return 6 * body; }
};

/// The layout of `problem`. ECPSIM_DEMAND (a bug in the caller) on: no bodies, a body whose h
/// differs from problem.h or that has contacts of its own, a contact whose body, G or window
/// index is out of range, a null shape, a contact of a body with itself, or a gripper whose jaws
/// are out of range, equal, or jaws of another gripper too.
IslandLayout MakeIslandLayout(const IslandProblem& problem);

/// Residual F(z) in physical units (rows as in IslandLayout) and, if `J` is not null, its
/// analytic Jacobian ∂F/∂z, with the dependence of both hulls' geometry on their bodies' ν⁺
/// through the end poses. Per contact, with F's end pose (c_F⁺, R_F⁺) and G's (c_G⁺, R_G⁺):
///   y_F = R_F⁺ᵀ(a1 − c_F⁺),  y_G = R_G⁺ᵀ(a2 − c_G⁺)  (a fixed G: y_G = a2, R_G⁺ = I)
///   N = Σ_j l_G,j R_G⁺ ∇g_j(y_G),  (n, t, o) = MakeContactFrame(N, tangent_reference)
///   a1 − a2 − s N = 0,  N + Σ_i l_i R_F⁺ ∇f_i(y_F) = 0,  Σ_j l_G,j − 1 = 0
///   0 ≤ l_i ⊥ −f_i(y_F) ≥ 0,  0 ≤ l_G,j ⊥ −g_j(y_G) ≥ 0,  0 ≤ p_n ⊥ s ≥ 0
///   v_c = (v_F⁺ + ω_F⁺ × (a1 − c_F⁺)) − (v_G + ω_G × (a2 − c_G⁺)),  v_r = n · (ω_F⁺ − ω_G)
///   e_t² μ p_n (t·v_c) + p_t σ = 0,  e_o² μ p_n (o·v_c) + p_o σ = 0,  e_r² μ p_n v_r + p_r σ = 0
///   0 ≤ σ ⊥ μ p_n − ‖(p_t/e_t, p_o/e_o, p_r/e_r)‖ ≥ 0
/// and the wrench enters F's Newton–Euler rows as in EvaluateMncp, and a dynamic G's with the
/// opposite force −(n p_n + t p_t + o p_o) at a2, i.e. the moment (a2 − c_G⁺) × (−force) − n p_r
/// about c_G⁺. Force and velocity are paired at the same points, so the contact's power on the
/// island is exactly force · v_c + p_r v_r for every z (the friction rows' dissipation); linear
/// momentum is exchanged exactly, and angular momentum about any point too wherever a1 = a2
/// (every solution: a1 ≠ a2 only when separated, where p = 0).
/// A gripper's jaws have their Newton–Euler rows replaced by ApplyGripperRows.
/// With `jacobian_is_zero` the caller promises J is already layout.size square and zero (as
/// SolveMcp hands it to its callback), and J is not cleared again.
/// AssembleMncp (mncp_assembly.h) over the island, with DenseMncpRows; then the grippers' rows.
void EvaluateIslandMncp(const IslandProblem& problem, const IslandLayout& layout,
                        const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J,
                        bool jacobian_is_zero = false);

/// EvaluateIslandMncp with the Jacobian assembled sparse (column-major, compressed): the same
/// assembly with SparseMncpRows (mncp_assembly.h) — per body its 6 × 6 Newton–Euler block, per
/// contact its rows over its own block and the ν⁺ of its one or two bodies and its wrench in
/// their Newton–Euler rows, each evaluated on that compact block — plus every diagonal entry
/// (zero where the Jacobian has none, so that a Newton matrix J + D keeps J's pattern). Cost and
/// storage grow with the bodies and contacts, not with the square of the unknowns. F equals
/// EvaluateIslandMncp's (x + (0 − f) = x − f, but for the sign of a zero), J up to the order of
/// its sums (round-off).
void EvaluateIslandMncpSparse(const IslandProblem& problem, const IslandLayout& layout,
                              const Eigen::VectorXd& z, Eigen::VectorXd* F,
                              Eigen::SparseMatrix<double>* J);

/// What the island's convergence measure measures against (see IslandMncpResidual); built by
/// MakeIslandResidualUnits (island_scaling.h) once per solve.
struct IslandResidualUnits {
  double tolerance = 1e-12;                 // the solver's tolerance on the measure
  std::vector<double> body_length;          // m, per body: its length L_b
  std::vector<double> contact_length;       // m, per contact: the length its rows are in
  std::vector<double> contact_coordinates;  // m, per contact: the largest |coordinate| of the
                                            // centres of mass (frame origins) it joins
};

/// The island's convergence measure, MncpResidual generalized: McpResidual of the scaled
/// problem (every row and unknown in its own unit, island_scaling.h), so each body's Newton–Euler
/// rows are measured in that body's impulse scale and a contact's rows in its contact scales.
/// As in MncpResidual a contact's rows that carry world-coordinate round-off are measured
/// against max(contact length, round-off length of its a1, a2, s and the coordinates of the
/// bodies it joins), and each body's moment rows against max(L_b, the largest such round-off
/// length of its contacts — as F, or as a dynamic G, whose moment rows carry (a2 − c_G⁺) × p).
/// For one body with fixed contacts it is MncpResidual to the bit.
double IslandMncpResidual(const IslandProblem& problem, const IslandLayout& layout,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& F,
                          const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale,
                          const IslandResidualUnits& units);

/// J: what the contacts added to the island's energy over the step — Σ_b StepEnergyGain of its
/// bodies (kinetic and gravitational energy gained beyond the applied loads' work) minus the
/// work of the kinematic bodies on it, Σ over their contacts of force · (v_G + ω_G × (a2 − c_G⁺))
/// + p_r n · ω_G (a kinematic body moves at its prescribed twist, so this is its contact
/// impulse's work exactly). What remains is the contacts' work at ν⁺, Σ force · v_c + p_r v_r —
/// friction only dissipates, the normal impulse works against a closing gap (≤ 0) or pushes a
/// start-of-step overlap out — and the implicit step's own losses (StepEnergyGain). A gripper's
/// jaws count as the kinematic bodies do: their own energy is the frame's and the actuator's
/// business, and their contact impulses' work on the other bodies (at the jaws' ν⁺) is taken
/// off. For one body with fixed contacts it is StepEnergyGain to the bit.
double IslandStepEnergyGain(const IslandProblem& problem, const IslandLayout& layout,
                            const Eigen::VectorXd& z);

/// G's end-of-step pose in contact `k` at z: a dynamic G's from its ν⁺ in z, a kinematic one's
/// from its prescribed twist; a fixed G's shape is in world coordinates (identity at the origin).
EndPose OtherEndPose(const IslandProblem& problem, const Eigen::VectorXd& z, int k);

/// N = Σ_j l_G,j R_G⁺ ∇g_j(y_G) of contact `k` at z (world; |N| ≈ 1 at a solution): the contact
/// frame is MakeContactFrame(N, tangent_reference).
Eigen::Vector3d IslandContactNormal(const IslandProblem& problem, const IslandLayout& layout,
                                    const Eigen::VectorXd& z, int k);

}  // namespace ecpsim::engine
