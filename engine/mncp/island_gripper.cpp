#include "engine/mncp/island_gripper.h"

#include <cmath>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/mncp/island_mncp.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

// the rows' linear combination: where each jaw's rows start in z and F, and the axis projections
struct Rows {
  int force0, moment0, force1, moment1;  // first row of each block
  Matrix3d along;                        // a aᵀ
  Matrix3d across;                       // I − a aᵀ
  double mean_mass;                      // kg: m̄
};

Rows MakeRows(const IslandGripper& g, const std::vector<BodyProblem>& bodies) {
  Rows r;
  r.force0 = IslandLayout::Velocity(g.jaws[0]);
  r.moment0 = r.force0 + 3;
  r.force1 = IslandLayout::Velocity(g.jaws[1]);
  r.moment1 = r.force1 + 3;
  r.along = g.axis * g.axis.transpose();
  r.across = Matrix3d::Identity() - r.along;
  r.mean_mass = 0.5 * (bodies[g.jaws[0]].mass + bodies[g.jaws[1]].mass);
  return r;
}

// the gripper's rows at z: the closing law's part that comes from the jaws' Newton–Euler force
// rows (R_0, R_1) is added by the caller; these are the rest
struct Constraints {
  Vector3d force0, moment0, force1, moment1;
};

Constraints Evaluate(const IslandGripper& g, const std::vector<BodyProblem>& bodies, const Rows& r,
                     const VectorXd& z) {
  const BodyProblem& jaw0 = bodies[g.jaws[0]];
  const BodyProblem& jaw1 = bodies[g.jaws[1]];
  const Vector3d v0 = z.segment<3>(r.force0), w0 = z.segment<3>(r.moment0);
  const Vector3d v1 = z.segment<3>(r.force1), w1 = z.segment<3>(r.moment1);
  Constraints c;
  c.force0 = -g.grip * g.axis + jaw0.mass * (r.across * (v0 - g.v[0]));
  c.moment0 = jaw0.inertia_world * (w0 - g.w[0]);
  c.force1 = r.mean_mass * (0.5 * g.axis.dot(v0 + v1) - g.centre_speed) * g.axis +
             jaw1.mass * (r.across * (v1 - g.v[1]));
  c.moment1 = jaw1.inertia_world * (w1 - g.w[1]);
  return c;
}

// the constraints' derivatives as (row block, column block, 3 × 3 matrix)
struct Block {
  int row, col;
  Matrix3d value;
};

std::array<Block, 5> ConstraintJacobian(const IslandGripper& g,
                                        const std::vector<BodyProblem>& bodies, const Rows& r) {
  const double m0 = bodies[g.jaws[0]].mass, m1 = bodies[g.jaws[1]].mass;
  return {Block{r.force0, r.force0, m0 * r.across},
          Block{r.moment0, r.moment0, bodies[g.jaws[0]].inertia_world},
          Block{r.force1, r.force0, 0.5 * r.mean_mass * r.along},
          Block{r.force1, r.force1, 0.5 * r.mean_mass * r.along + m1 * r.across},
          Block{r.moment1, r.moment1, bodies[g.jaws[1]].inertia_world}};
}

// the virtual-work row's combination of the jaws' force rows: ½ a aᵀ (R_0 − R_1)
Vector3d ClosingLaw(const Rows& r, const Vector3d& force0, const Vector3d& force1) {
  return 0.5 * r.along * (force0 - force1);
}

void ReplaceRows(const Rows& r, const Constraints& c, VectorXd& F) {
  F.segment<3>(r.force0) = ClosingLaw(r, F.segment<3>(r.force0), F.segment<3>(r.force1)) + c.force0;
  F.segment<3>(r.moment0) = c.moment0;
  F.segment<3>(r.force1) = c.force1;
  F.segment<3>(r.moment1) = c.moment1;
}

}  // namespace

IslandGripper MakeIslandGripper(const Gripper& gripper, const BodyProblem& jaw0,
                                const BodyProblem& jaw1, int jaw0_index, int jaw1_index, double t,
                                double h) {
  const double force = gripper.force(t);
  if (!(force >= 0)) {
    throw InputError(fmt::format(
        "gripper '{}': force = {} N at t = {} s: expected a closing force ≥ 0 N (the jaws "
        "open only as far as the bodies they hold push them)",
        gripper.name, force, t));
  }
  // the frame's step twist only for its checks (a turn of π or more per step is refused)
  gripper.motion->StepTwist(t, h);
  const KinematicPose frame = gripper.motion->PoseAt(t + h);
  IslandGripper g;
  g.jaws = {jaw0_index, jaw1_index};
  g.axis = ClosingAxis(gripper, frame);
  g.grip = h * force;
  const std::array<const BodyProblem*, 2> jaws = {&jaw0, &jaw1};
  Vector3d target_centre = Vector3d::Zero(), start_centre = Vector3d::Zero();
  for (int j = 0; j < 2; ++j) {
    const KinematicPose target = JawOnFrame(gripper, j, frame);
    const Eigen::Quaterniond turn_to = target.q * Eigen::Quaterniond(jaws[j]->R).conjugate();
    g.v[j] = (target.p - jaws[j]->c) / h;
    g.w[j] = QuaternionLog(turn_to.normalized()) / h;
    target_centre += 0.5 * target.p;
    start_centre += 0.5 * jaws[j]->c;
  }
  g.centre_speed = g.axis.dot(target_centre - start_centre) / h;
  return g;
}

void SetGripperFreeFlight(const IslandGripper& g, std::vector<BodyProblem>& bodies) {
  // with no contact: a·(v_0 + v_1) = 2 u and ½ (m_0 (x_0 − a·v_0) − a·p_0 − m_1 (x_1 − a·v_1) +
  // a·p_1) = grip, x_j = a·v_j⁺, p_j the applied impulses
  BodyProblem& jaw0 = bodies[g.jaws[0]];
  BodyProblem& jaw1 = bodies[g.jaws[1]];
  const Vector3d& a = g.axis;
  const double m0 = jaw0.mass, m1 = jaw1.mass, u = g.centre_speed;
  const double momentum0 = m0 * a.dot(jaw0.v) + a.dot(jaw0.p_ext.head<3>());
  const double momentum1 = m1 * a.dot(jaw1.v) + a.dot(jaw1.p_ext.head<3>());
  const double x0 = (2 * g.grip + momentum0 - momentum1 + 2 * m1 * u) / (m0 + m1);
  const double x1 = 2 * u - x0;
  jaw0.free.v = g.v[0] - a.dot(g.v[0]) * a + x0 * a;
  jaw1.free.v = g.v[1] - a.dot(g.v[1]) * a + x1 * a;
  jaw0.free.w = g.w[0];
  jaw1.free.w = g.w[1];
}

void ApplyGripperRows(const IslandGripper& g, const std::vector<BodyProblem>& bodies,
                      const VectorXd& z, VectorXd& F, Eigen::MatrixXd* J) {
  const Rows r = MakeRows(g, bodies);
  ReplaceRows(r, Evaluate(g, bodies, r, z), F);
  if (!J) return;
  J->middleRows<3>(r.force0) =
      0.5 * r.along * (J->middleRows<3>(r.force0) - J->middleRows<3>(r.force1));
  for (int row : {r.moment0, r.force1, r.moment1}) J->middleRows<3>(row).setZero();
  for (const Block& b : ConstraintJacobian(g, bodies, r)) J->block<3, 3>(b.row, b.col) += b.value;
}

void ApplyGripperRows(const IslandGripper& g, const std::vector<BodyProblem>& bodies,
                      const VectorXd& z, VectorXd& F,
                      std::vector<Eigen::Triplet<double>>* triplets) {
  const Rows r = MakeRows(g, bodies);
  ReplaceRows(r, Evaluate(g, bodies, r, z), F);
  if (!triplets) return;
  const auto in_block = [](int row, int first) { return row >= first && row < first + 3; };
  std::vector<Eigen::Triplet<double>> mapped;
  mapped.reserve(triplets->size());
  for (const Eigen::Triplet<double>& e : *triplets) {
    const int row = static_cast<int>(e.row());
    const bool force0 = in_block(row, r.force0), force1 = in_block(row, r.force1);
    if (!force0 && !force1 && !in_block(row, r.moment0) && !in_block(row, r.moment1)) {
      mapped.push_back(e);
      continue;
    }
    if (!force0 && !force1) continue;  // a moment row: replaced by its constraint
    // ½ a aᵀ (R_0 − R_1): entry (k, col) of R_0 (R_1) adds ±½ a_i a_k to rows i of jaw 0's
    const int k = row - (force0 ? r.force0 : r.force1);
    const double sign = force0 ? 0.5 : -0.5;
    for (int i = 0; i < 3; ++i) {
      const double value = sign * r.along(i, k) * e.value();
      if (value != 0) mapped.emplace_back(r.force0 + i, e.col(), value);
    }
  }
  for (const Block& b : ConstraintJacobian(g, bodies, r))
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        if (b.value(i, j) != 0) mapped.emplace_back(b.row + i, b.col + j, b.value(i, j));
  // the diagonal stays in the pattern (EvaluateIslandMncpSparse's promise)
  for (int first : {r.force0, r.moment0, r.force1, r.moment1})
    for (int i = 0; i < 3; ++i) mapped.emplace_back(first + i, first + i, 0.0);
  *triplets = std::move(mapped);
}

}  // namespace ecpsim::engine
