#include "engine/mncp/island_mncp.h"

#include <algorithm>
#include <array>
#include <cfloat>

#include <Eigen/SparseCore>

#include "common/errors.h"
#include "engine/mncp/mncp_assembly.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

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
const StepMotion* OtherMotion(const IslandContact& cp, const PerBody<StepMotion>& bodies,
                              const std::vector<StepMotion>& kinematic) {
  if (cp.other_kind == Other::kBody) return &bodies[cp.other];
  if (cp.other_kind == Other::kKinematic) return &kinematic[cp.other];
  return nullptr;
}

// The round-off that a creeping contact's friction impulses carry (IslandContact::stick_creep).
// Sticking with creep ε is the viscous law p = −e² μ p_n v / (σ + ε): the slip velocity v at the
// ECP is a difference of the two sides' velocities, each exact to a few ulps of its magnitude u,
// so at a solution p is only known to e² μ p_n · ulps · u / ε — 2e-9 μ p_n for ε = 1e-7 u, far
// above the tolerance's share of the bodies' impulse scale when the bodies move (two falling
// dominoes leaning on each other). The Newton–Euler rows that carry these impulses are measured
// against this floor, as the contact rows are against the coordinates' round-off.
struct CreepRoundOff {
  double force = 0;   // N·s: of p_t and p_o
  double torque = 0;  // N·m·s: of p_r
};

CreepRoundOff CreepFrictionRoundOff(const IslandProblem& problem, const IslandLayout& layout,
                                    const VectorXd& z, int k) {
  const IslandContact& cp = problem.contacts[k];
  if (!(cp.stick_creep > 0)) return {};
  const MncpLayout::Contact& L = layout.contacts[k];
  const Vector3d a1 = z.segment<3>(L.a1);
  const int col = IslandLayout::Velocity(cp.body);
  double speed = z.segment<3>(col).norm() +
                 z.segment<3>(col + 3).norm() * (a1 - problem.bodies[cp.body].c).norm();
  double spin = z.segment<3>(col + 3).norm();
  if (cp.other_kind == Other::kBody) {
    const int other = IslandLayout::Velocity(cp.other);
    speed += z.segment<3>(other).norm() +
             z.segment<3>(other + 3).norm() * (a1 - problem.bodies[cp.other].c).norm();
    spin += z.segment<3>(other + 3).norm();
  } else if (cp.other_kind == Other::kKinematic) {
    const KinematicBody& g = problem.kinematic[cp.other];
    speed += g.v.norm() + g.w.norm() * (a1 - g.c).norm();
    spin += g.w.norm();
  }
  const Friction& fr = cp.friction;
  const double p_n = std::max(z[L.p_n], 0.0);
  const double slip = std::max(z[L.sigma], 0.0) + cp.stick_creep;
  const double ulp = kCoordinateRoundOffUlps * DBL_EPSILON;
  CreepRoundOff round_off;
  round_off.force = std::max(fr.e_t * fr.e_t, fr.e_o * fr.e_o) * fr.mu * p_n * ulp * speed / slip;
  round_off.torque = fr.e_r * fr.e_r * fr.mu * p_n * ulp * spin / slip;
  return round_off;
}

// the island's bodies and contacts as AssembleMncp walks them
class IslandView {
 public:
  IslandView(const IslandProblem& problem, const IslandLayout& layout)
      : problem_(problem), layout_(layout), kinematic_(KinematicMotions(problem)) {}

  double h() const { return problem_.h; }
  int NumBodies() const { return layout_.num_bodies; }
  const BodyProblem& Body(int b) const { return problem_.bodies[b]; }
  int Column(int b) const { return IslandLayout::Velocity(b); }
  int NumContacts() const { return static_cast<int>(problem_.contacts.size()); }
  const MncpLayout::Contact& Layout(int k) const { return layout_.contacts[k]; }
  ContactLink Link(int k, const PerBody<StepMotion>& motions) const {
    const IslandContact& cp = problem_.contacts[k];
    return {SidesOf(cp), cp.body, OtherMotion(cp, motions, kinematic_)};
  }

 private:
  const IslandProblem& problem_;
  const IslandLayout& layout_;
  const std::vector<StepMotion> kinematic_;
};

}  // namespace

ContactSides SidesOf(const IslandContact& cp) {
  return {cp.hull,     &cp.window,           cp.other_shape, &cp.other_window,
          cp.friction, cp.tangent_reference, cp.stick_creep};
}

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
    // a fixed half-space's contact in the plane form (MncpLayout), without a2, s and l_G
    const bool plane = cp.other_kind == Other::kFixed && cp.other_shape->IsHalfSpace();
    counts.push_back(
        {static_cast<int>(cp.window.size()), plane ? 0 : static_cast<int>(cp.other_window.size())});
  }
  // each jaw of at most one gripper (checked only where there are grippers: this runs every solve)
  if (!problem.grippers.empty()) {
    std::vector<bool> jaw(num_bodies, false);
    for (const IslandGripper& g : problem.grippers) {
      for (int b : g.jaws) {
        ECPSIM_DEMAND(b >= 0 && b < num_bodies && !jaw[b]);
        jaw[b] = true;
      }
    }
  }
  const MncpLayout blocks = LayOutContacts(IslandLayout::Velocity(num_bodies), counts);
  IslandLayout layout;
  layout.num_bodies = num_bodies;
  layout.num_free = blocks.num_free;
  layout.size = blocks.size;
  layout.contacts = blocks.contacts;
  return layout;
}

void EvaluateIslandMncp(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                        VectorXd* F, MatrixXd* J, bool jacobian_is_zero) {
  DenseMncpRows rows(layout.size, z, *F, J, jacobian_is_zero);
  AssembleMncp(IslandView(problem, layout), rows);
  for (const IslandGripper& g : problem.grippers) ApplyGripperRows(g, problem.bodies, z, *F, J);
}

void EvaluateIslandMncpSparse(const IslandProblem& problem, const IslandLayout& layout,
                              const VectorXd& z, VectorXd* F, Eigen::SparseMatrix<double>* J) {
  std::vector<Eigen::Triplet<double>> triplets;
  SparseMncpRows rows(layout.size, z, *F, J ? &triplets : nullptr);
  AssembleMncp(IslandView(problem, layout), rows);
  for (const IslandGripper& g : problem.grippers)
    ApplyGripperRows(g, problem.bodies, z, *F, J ? &triplets : nullptr);
  if (!J) return;
  J->resize(layout.size, layout.size);
  J->setFromTriplets(triplets.begin(), triplets.end());
}

double IslandMncpResidual(const IslandProblem& problem, const IslandLayout& layout,
                          const VectorXd& z, const VectorXd& F, const VectorXd& row_scale,
                          const VectorXd& var_scale, const IslandResidualUnits& units) {
  // row by row, as MncpResidual: each contact's rows in its own length, floored by round-off
  ScaledRowResidual r(layout.num_free, z, F, row_scale, var_scale);
  // per body the divisors of its force and moment rows
  PerBody<std::array<double, 2>> divisors(layout.num_bodies, {1.0, 1.0});
  const auto force_factor = [&](int b) -> double& { return divisors[b][0]; };
  const auto moment_factor = [&](int b) -> double& { return divisors[b][1]; };
  for (size_t k = 0; k < layout.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const MncpLayout::Contact& L = layout.contacts[k];
    const double round_off =
        ContactRoundOffLength(L, z, units.contact_coordinates[k], units.tolerance);
    r.AddContact(L, std::max(1.0, round_off / units.contact_length[k]));
    const CreepRoundOff creep = CreepFrictionRoundOff(problem, layout, z, static_cast<int>(k));
    // each body's moment rows carry r × p of its contacts, in its own length; its Newton–Euler
    // rows carry a creeping contact's friction impulses with their round-off
    for (int b : {cp.body, cp.other_kind == Other::kBody ? cp.other : -1}) {
      if (b < 0) continue;
      moment_factor(b) = std::max(moment_factor(b), round_off / units.body_length[b]);
      if (!(cp.stick_creep > 0)) continue;
      const int col = IslandLayout::Velocity(b);
      const double impulse = 1 / row_scale[col];      // N·s: the body's impulse scale
      const double angular = 1 / row_scale[col + 3];  // N·m·s
      const double arm = (z.segment<3>(L.a1) - problem.bodies[b].c).norm();
      force_factor(b) = std::max(force_factor(b), creep.force / (units.tolerance * impulse));
      moment_factor(b) = std::max(moment_factor(b),
                                  (creep.force * arm + creep.torque) / (units.tolerance * angular));
    }
  }
  for (int b = 0; b < layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    for (int i = 0; i < 3; ++i) {
      r.AddRow(col + i, force_factor(b));
      r.AddRow(col + 3 + i, moment_factor(b));
    }
  }
  return r.value();
}

double IslandStepEnergyGain(const IslandProblem& problem, const IslandLayout& layout,
                            const VectorXd& z) {
  PerBody<char> jaw(layout.num_bodies, 0);  // bool: std::vector<bool> has no references
  for (const IslandGripper& g : problem.grippers)
    for (int b : g.jaws) jaw[b] = 1;
  const auto body_gain = [&](int b) {
    if (jaw[b]) return 0.0;
    const int col = IslandLayout::Velocity(b);
    return StepEnergyGain(problem.bodies[b], z.segment<3>(col), z.segment<3>(col + 3));
  };
  double gain = body_gain(0);
  for (int b = 1; b < layout.num_bodies; ++b) gain += body_gain(b);
  // the work of the bodies that drive the others — kinematic bodies and jaws — on them: their
  // contact impulse times their own velocity at the contact point
  const std::vector<StepMotion> kinematic = KinematicMotions(problem);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const bool other_drives =
        cp.other_kind == Other::kKinematic || (cp.other_kind == Other::kBody && jaw[cp.other]);
    const bool body_drives = jaw[cp.body];
    // a driver against a driver, or against a fixed obstacle, moves no body of the balance
    if (body_drives == other_drives || (body_drives && cp.other_kind != Other::kBody)) continue;
    const MncpLayout::Contact& L = layout.contacts[k];
    StepMotion other;
    if (cp.other_kind == Other::kKinematic) {
      other = kinematic[cp.other];
    } else {
      const int col = IslandLayout::Velocity(cp.other);
      other.end = OtherEndPose(problem, z, static_cast<int>(k));
      other.v = z.segment<3>(col);
      other.w = z.segment<3>(col + 3);
    }
    const ContactFrame frame =
        MakeContactFrame(ContactNormalCombination(SidesOf(cp), L, &other, z), cp.tangent_reference);
    const Vector3d force = frame.n * z[L.p_n] + frame.t * z[L.p_t] + frame.o * z[L.p_o];
    if (other_drives) {
      const Vector3d r_other = z.segment<3>(L.a2) - other.end.c;
      gain -= force.dot(other.v + other.w.cross(r_other)) + z[L.p_r] * frame.n.dot(other.w);
    } else {
      // the jaw is F: its impulse on G is −force at a2 and −n p_r
      const int col = IslandLayout::Velocity(cp.body);
      const Vector3d v = z.segment<3>(col), w = z.segment<3>(col + 3);
      const Vector3d r_body = z.segment<3>(L.a1) - PoseAfterStep(problem.bodies[cp.body], v, w).c;
      gain += force.dot(v + w.cross(r_body)) + z[L.p_r] * frame.n.dot(w);
    }
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
    return ContactNormalCombination(SidesOf(cp), layout.contacts[k], nullptr, z);
  StepMotion other;
  other.end = OtherEndPose(problem, z, k);
  return ContactNormalCombination(SidesOf(cp), layout.contacts[k], &other, z);
}

}  // namespace ecpsim::engine
