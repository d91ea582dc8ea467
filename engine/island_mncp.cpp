#include "engine/island_mncp.h"

#include <algorithm>
#include <array>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

ContactSides Sides(const IslandContact& cp) {
  return {cp.hull, &cp.window, cp.other_shape, &cp.other_window, cp.friction,
          cp.tangent_reference, cp.stick_creep};
}

// the kinematic bodies' motions over the step: prescribed, no unknowns
std::vector<StepMotion> KinematicMotions(const IslandProblem& problem) {
  std::vector<StepMotion> motions;
  for (const KinematicBody& k : problem.kinematic) {
    StepMotion m;
    m.end = PoseAfterStep(k.c, k.R, problem.h, k.v, k.w);
    m.v = k.v;
    m.w = k.w;
    motions.push_back(m);
  }
  return motions;
}

// G's motion for contact `cp`: null for a fixed G
const StepMotion* OtherMotion(const IslandContact& cp, const std::vector<StepMotion>& bodies,
                              const std::vector<StepMotion>& kinematic) {
  if (cp.other_kind == Other::kBody) return &bodies[cp.other];
  if (cp.other_kind == Other::kKinematic) return &kinematic[cp.other];
  return nullptr;
}

}  // namespace

IslandLayout MakeIslandLayout(const IslandProblem& problem) {
  const int num_bodies = static_cast<int>(problem.bodies.size());
  ECPSIM_DEMAND(num_bodies > 0);
  for (const BodyProblem& body : problem.bodies)
    ECPSIM_DEMAND(body.h == problem.h && body.contacts.empty());
  std::vector<std::array<int, 2>> counts;
  for (const IslandContact& cp : problem.contacts) {
    ECPSIM_DEMAND(cp.body >= 0 && cp.body < num_bodies && cp.hull && cp.other_shape);
    if (cp.other_kind == Other::kKinematic)
      ECPSIM_DEMAND(cp.other >= 0 && cp.other < static_cast<int>(problem.kinematic.size()));
    if (cp.other_kind == Other::kBody)
      ECPSIM_DEMAND(cp.other >= 0 && cp.other < num_bodies && cp.other != cp.body);
    for (int i : cp.window) ECPSIM_DEMAND(i >= 0 && i < cp.hull->NumConstraints());
    for (int j : cp.other_window) ECPSIM_DEMAND(j >= 0 && j < cp.other_shape->NumConstraints());
    counts.push_back(
        {static_cast<int>(cp.window.size()), static_cast<int>(cp.other_window.size())});
  }
  const MncpLayout blocks = LayOutContacts(IslandLayout::Velocity(num_bodies), counts);
  IslandLayout layout;
  layout.num_bodies = num_bodies;
  layout.num_free = blocks.num_free;
  layout.size = blocks.size;
  layout.contacts = blocks.contacts;
  return layout;
}

void EvaluateIslandMncp(const IslandProblem& problem, const IslandLayout& layout,
                        const VectorXd& z, VectorXd* F, MatrixXd* J) {
  F->setZero(layout.size);
  if (J) J->setZero(layout.size, layout.size);
  // per body the contact-free Newton–Euler rows, then per contact its rows and its wrenches
  std::vector<StepMotion> bodies;
  for (int b = 0; b < layout.num_bodies; ++b)
    bodies.push_back(AddBodyRows(problem.bodies[b], IslandLayout::Velocity(b), z, *F, J));
  const std::vector<StepMotion> kinematic = KinematicMotions(problem);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    AddContactRows(Sides(cp), layout.contacts[k], bodies[cp.body],
                   OtherMotion(cp, bodies, kinematic), problem.h, z, *F, J);
  }
}

double IslandMncpResidual(const IslandProblem& problem, const IslandLayout& layout,
                          const VectorXd& z, const VectorXd& F, const VectorXd& row_scale,
                          const VectorXd& var_scale, const IslandResidualUnits& units) {
  // row by row, as MncpResidual: each contact's rows in its own length, floored by round-off
  ScaledRowResidual r(layout.num_free, z, F, row_scale, var_scale);
  std::vector<double> moment_factor(layout.num_bodies, 1.0);
  for (size_t k = 0; k < layout.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const MncpLayout::Contact& L = layout.contacts[k];
    const double round_off =
        ContactRoundOffLength(L, z, units.contact_coordinates[k], units.tolerance);
    r.AddContact(L, std::max(1.0, round_off / units.contact_length[k]));
    // each body's moment rows carry r × p of its contacts, in its own length
    for (int b : {cp.body, cp.other_kind == Other::kBody ? cp.other : -1}) {
      if (b < 0) continue;
      moment_factor[b] =
          std::max(moment_factor[b], std::max(1.0, round_off / units.body_length[b]));
    }
  }
  for (int b = 0; b < layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    for (int i = 0; i < 3; ++i) {
      r.AddRow(col + i, 1);
      r.AddRow(col + 3 + i, moment_factor[b]);
    }
  }
  return r.value();
}

double IslandStepEnergyGain(const IslandProblem& problem, const IslandLayout& layout,
                            const VectorXd& z) {
  const auto body_gain = [&](int b) {
    const int col = IslandLayout::Velocity(b);
    return StepEnergyGain(problem.bodies[b], z.segment<3>(col), z.segment<3>(col + 3));
  };
  double gain = body_gain(0);
  for (int b = 1; b < layout.num_bodies; ++b) gain += body_gain(b);
  // the kinematic bodies' work: their contact impulse times their prescribed velocities
  const std::vector<StepMotion> kinematic = KinematicMotions(problem);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    if (cp.other_kind != Other::kKinematic) continue;
    const MncpLayout::Contact& L = layout.contacts[k];
    const StepMotion& other = kinematic[cp.other];
    const ContactFrame frame = MakeContactFrame(
        ContactNormalCombination(Sides(cp), L, &other, z), cp.tangent_reference);
    const Vector3d force = frame.n * z[L.p_n] + frame.t * z[L.p_t] + frame.o * z[L.p_o];
    const Vector3d r_other = z.segment<3>(L.a2) - other.end.c;
    gain -= force.dot(other.v + other.w.cross(r_other)) + z[L.p_r] * frame.n.dot(other.w);
  }
  return gain;
}

EndPose OtherEndPose(const IslandProblem& problem, const VectorXd& z, int k) {
  const IslandContact& cp = problem.contacts[k];
  if (cp.other_kind == Other::kBody) {
    const int col = IslandLayout::Velocity(cp.other);
    return PoseAfterStep(problem.bodies[cp.other], z.segment<3>(col), z.segment<3>(col + 3));
  }
  if (cp.other_kind == Other::kKinematic) {
    const KinematicBody& g = problem.kinematic[cp.other];
    return PoseAfterStep(g.c, g.R, problem.h, g.v, g.w);
  }
  return {Vector3d::Zero(), Eigen::Matrix3d::Identity()};
}

Vector3d IslandContactNormal(const IslandProblem& problem, const IslandLayout& layout,
                             const VectorXd& z, int k) {
  const IslandContact& cp = problem.contacts[k];
  if (cp.other_kind == Other::kFixed)
    return ContactNormalCombination(Sides(cp), layout.contacts[k], nullptr, z);
  StepMotion other;
  other.end = OtherEndPose(problem, z, k);
  return ContactNormalCombination(Sides(cp), layout.contacts[k], &other, z);
}

}  // namespace ecpsim::engine
