#include "engine/models/multipatch_balance.h"

#include <vector>

#include <Eigen/LU>  // Matrix3d::inverse

#include "engine/models/balanced_start.h"

namespace ecpsim::engine {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

StartBalance BalanceMultiPatchSlidingStart(const MultiPatchProblem& problem,
                                           const MncpLayout& layout, double active_fraction,
                                           VectorXd& z) {
  const BodyProblem& body = problem.body;
  const int parts = static_cast<int>(body.contacts.size());
  if (problem.num_groups != 1 || parts < 2) return StartBalance::kUnbalanced;
  for (const MncpLayout::Contact& L : layout.contacts) {
    if (!L.on_plane() || !(z[L.p_n] > 0) || !(z[L.sigma] > 0) ||
        !CarriedByOneFace(L, active_fraction, z))
      return StartBalance::kUnbalanced;
  }
  // one group: one scene contact, so one plane and one friction for every part
  const ContactFrame frame = MultiPatchFrame(body.contacts[0]);
  const Friction& friction = body.contacts[0].friction;

  // the balance works on its own copy; z takes it only once it is complete
  VectorXd balanced = z;
  // each part's ECP on the part, where the last step left it: at that step's end pose, which is
  // this step's start (c, R)
  std::vector<Vector3d> on_part(parts);
  for (int i = 0; i < parts; ++i)
    on_part[i] = body.R.transpose() * (z.segment<3>(layout.contacts[i].a1) - body.c);
  const auto carry = [&](const Vector3d& v, const Vector3d& w) {
    const EndPose end = PoseAfterStep(body, v, w);
    for (int i = 0; i < parts; ++i)
      balanced.segment<3>(layout.contacts[i].a1) = end.c + end.R * on_part[i];
  };

  // the parts' summed wrench at their combined ECP, the ECPs carried to the warm start's end pose
  carry(z.segment<3>(0), z.segment<3>(3));
  const Vector3d a1 = CombinedEcp(problem, layout, balanced, 0);
  SlidingBalance sum{z.segment<3>(0), z.segment<3>(3), a1, Vector3d::Zero(), 0, 0};
  for (const MncpLayout::Contact& L : layout.contacts) {
    const Vector3d d = balanced.segment<3>(L.a1) - a1;
    sum.friction +=
        Vector3d(z[L.p_t], z[L.p_o], EquivalentMoment(frame, d, z[L.p_t], z[L.p_o], z[L.p_r]));
    sum.p_n += z[L.p_n];
    sum.slip_norm += z[L.p_n] * z[L.sigma];
  }
  sum.slip_norm /= sum.p_n;
  // (the warm start's slip turns little from step to step while its loads change: a friction
  // that agrees with it says nothing of the other rows)
  const StartBalance result = SweepAndPolish(body, frame, friction, kMultiPatchBalanceTolerance,
                                             AgreeingStart::kSweep, sum);
  if (result == StartBalance::kUnbalanced) return result;

  // the ECPs carried to the balanced end pose, and the loads that put their p_n-weighted mean at
  // the balanced combined ECP a*: the least change δ of the warm start's p_n,i with
  // Σ δ_i = p_n − Σ p_n,i and Σ (p_n,i + δ_i) (a1_i − a*) = 0 along t and o (the normal loads'
  // moment about a* vanishes, as the single-patch wrench's at its ECP does):
  // δ = Aᵀ (A Aᵀ)⁻¹ b with A's rows 1, t·(a1_i − a*), o·(a1_i − a*)
  carry(sum.v, sum.w);
  Eigen::Matrix<double, 3, Eigen::Dynamic> A(3, parts);
  Vector3d b(sum.p_n, 0, 0);
  for (int i = 0; i < parts; ++i) {
    const MncpLayout::Contact& L = layout.contacts[i];
    const Vector3d r = balanced.segment<3>(L.a1) - sum.a1;
    A.col(i) = Vector3d(1, frame.t.dot(r), frame.o.dot(r));
    b -= z[L.p_n] * A.col(i);
  }
  const Matrix3d gram = A * A.transpose();
  const VectorXd change = A.transpose() * (gram.inverse() * b);
  if (!change.allFinite()) return StartBalance::kUnbalanced;
  for (int i = 0; i < parts; ++i) {
    const MncpLayout::Contact& L = layout.contacts[i];
    balanced[L.p_n] = z[L.p_n] + change[i];
    if (!(balanced[L.p_n] > 0)) return StartBalance::kUnbalanced;
  }

  // each part's share of the friction about the combined ECP, at the group's slip
  balanced.segment<3>(0) = sum.v;
  balanced.segment<3>(3) = sum.w;
  const Vector3d combined = CombinedEcp(problem, layout, balanced, 0);
  for (const MncpLayout::Contact& L : layout.contacts) {
    const double share = balanced[L.p_n] / sum.p_n;
    const double p_t = share * sum.friction[0], p_o = share * sum.friction[1];
    const Vector3d d = balanced.segment<3>(L.a1) - combined;
    balanced[L.p_t] = p_t;
    balanced[L.p_o] = p_o;
    // p_r,i such that p_rE,i = share × p_r
    balanced[L.p_r] = share * sum.friction[2] - EquivalentMoment(frame, d, p_t, p_o, 0);
    balanced[L.sigma] = sum.slip_norm;
  }
  z.swap(balanced);
  return result;
}

}  // namespace ecpsim::engine
