#pragma once
// A gripper's two jaws in an island's MNCP (scene.h Gripper; engine/README.md, "Grippers"): the
// jaws are dynamic bodies whose six Newton–Euler rows each are replaced by the gripper's
// equations — across the closing axis and in orientation each jaw reaches the frame's pose at
// the end of the step; along it, the jaws' midpoint reaches the frame's centre and the coupled
// closing motion obeys Newton's law under the actuator's force and the jaws' contacts.

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "engine/mncp/mncp_system.h"
#include "engine/scene.h"

namespace ecpsim::engine {

/// One gripper over one step, in island body indices and world coordinates.
struct IslandGripper {
  std::array<int, 2> jaws = {-1, -1};               // island bodies: jaws[0] closes along +axis
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // world, unit, the frame's at the step's end
  // m/s: each jaw's velocity that takes its CM onto the frame's path at the step's end (its
  // component along the axis unused)
  std::array<Eigen::Vector3d, 2> v;
  // rad/s: each jaw's angular velocity that turns it into the frame's orientation at the end
  std::array<Eigen::Vector3d, 2> w;
  double centre_speed = 0;  // m/s along axis: takes the jaws' midpoint to the frame's centre
  double grip = 0;          // N·s: the actuator's closing impulse on each jaw, h · force(t)
};

/// The gripper's targets for the step [t, t + h] from its jaws' start-of-step problems (island
/// indices `jaw0`, `jaw1`): the frame's pose at t + h, each jaw's pose in it.
/// @throws InputError (naming the gripper and t) if the force at t is negative or not finite,
///         or as KinematicMotion::PoseAt / StepTwist.
IslandGripper MakeIslandGripper(const Gripper& gripper, const BodyProblem& jaw0,
                                const BodyProblem& jaw1, int jaw0_index, int jaw1_index, double t,
                                double h);

/// Sets the jaws' free-flight velocities (BodyProblem::free): the solution of the gripper's
/// equations when no contact acts, in closed form.
void SetGripperFreeFlight(const IslandGripper& gripper, std::vector<BodyProblem>& bodies);

/// Replaces the jaws' Newton–Euler rows of F (and of J, dense, when not null) — evaluated with
/// every contact's wrench added — by the gripper's rows, with v_j, ω_j the jaws' ν⁺ in z, R_j
/// their Newton–Euler force rows, P = I − a aᵀ, m̄ = (m_0 + m_1) / 2:
///   jaw 0, force:  a (½ aᵀ(R_0 − R_1) − grip) + m_0 P (v_0 − v_0*)
///   jaw 1, force:  a m̄ (½ aᵀ(v_0 + v_1) − centre_speed) + m_1 P (v_1 − v_1*)
///   jaw j, moment: I_j (ω_j − ω_j*)   (I_j the jaw's world inertia at the step's start)
/// The first is the virtual work of the coupled closing motion (δv_0 = a, δv_1 = −a), the others
/// the constraints; every row stays in N·s or N·m·s, and ∂/∂ν⁺ of a jaw's own rows is
/// non-singular (m_j P + a aᵀ terms, I_j).
void ApplyGripperRows(const IslandGripper& gripper, const std::vector<BodyProblem>& bodies,
                      const Eigen::VectorXd& z, Eigen::VectorXd& F, Eigen::MatrixXd* J);

/// The same on a Jacobian given as triplets (summed when assembled): the jaws' force-row
/// triplets are mapped through the rows' linear combination, their moment-row triplets dropped,
/// and the constraints' entries appended.
void ApplyGripperRows(const IslandGripper& gripper, const std::vector<BodyProblem>& bodies,
                      const Eigen::VectorXd& z, Eigen::VectorXd& F,
                      std::vector<Eigen::Triplet<double>>* triplets);

}  // namespace ecpsim::engine
