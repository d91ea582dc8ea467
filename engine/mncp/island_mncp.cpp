#include "engine/mncp/island_mncp.h"

#include <algorithm>
#include <array>
#include <cfloat>

#include <Eigen/SparseCore>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

ContactSides Sides(const IslandContact& cp) {
  return {cp.hull,     &cp.window,           cp.other_shape, &cp.other_window,
          cp.friction, cp.tangent_reference, cp.stick_creep};
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

// per-body values of an island: in place for one body (the usual island, whose MNCP is evaluated
// and measured every Newton iteration: no heap allocation), in a vector for several
template <typename T>
class PerBody {
 public:
  explicit PerBody(int count) {
    if (count > 1) several_.resize(count);
  }
  PerBody(int count, const T& value) : single_(value) {
    if (count > 1) several_.assign(count, value);
  }
  T& operator[](int b) { return several_.empty() ? single_ : several_[b]; }
  const T& operator[](int b) const { return several_.empty() ? single_ : several_[b]; }

 private:
  T single_{};
  std::vector<T> several_;
};

// G's motion for contact `cp`: null for a fixed G
template <typename Bodies>
const StepMotion* OtherMotion(const IslandContact& cp, const Bodies& bodies,
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

// A contact's rows evaluated on a compact block of the unknowns it touches: F's ν⁺ (6), a
// dynamic G's ν⁺ (6), then its free block (a1, a2, s, p_t, p_o, p_r; on a plane a1, p_t, p_o,
// p_r) and its complementarity block (l, l_G, p_n, σ), each contiguous in the island's layout too
struct LocalContact {
  std::vector<int> global;  // local index → index in the island's z
  MncpLayout::Contact L;    // the contact's layout in local indices
  int other_column = -1;    // local column of a dynamic G's ν⁺
  int num_body_rows = 6;    // the Newton–Euler rows first: 6, or 12 with a dynamic G
};

LocalContact MakeLocalContact(const IslandContact& cp, const MncpLayout::Contact& L) {
  LocalContact local;
  for (int i = 0; i < 6; ++i) local.global.push_back(IslandLayout::Velocity(cp.body) + i);
  if (cp.other_kind == Other::kBody) {
    local.other_column = 6;
    local.num_body_rows = 12;
    for (int i = 0; i < 6; ++i) local.global.push_back(IslandLayout::Velocity(cp.other) + i);
  }
  const int free = static_cast<int>(local.global.size());
  for (int i = L.a1; i <= L.p_r; ++i) local.global.push_back(i);
  const int complementarity = static_cast<int>(local.global.size());
  const int count = L.l_count + L.l_g_count + 2;
  for (int i = 0; i < count; ++i) local.global.push_back(L.l + i);
  local.L = L;
  const int shift_free = free - L.a1, shift_complementarity = complementarity - L.l;
  for (int* index : {&local.L.a1, &local.L.p_t, &local.L.p_o, &local.L.p_r}) *index += shift_free;
  if (!L.on_plane())
    for (int* index : {&local.L.a2, &local.L.s}) *index += shift_free;
  for (int* index : {&local.L.l, &local.L.l_g, &local.L.p_n, &local.L.sigma})
    *index += shift_complementarity;
  return local;
}

// the non-zero entries of a dense local block as triplets of the island's matrix
void ScatterNonZeros(const Eigen::MatrixXd& block, const std::vector<int>& global,
                     std::vector<Eigen::Triplet<double>>& triplets) {
  for (Eigen::Index j = 0; j < block.cols(); ++j)
    for (Eigen::Index i = 0; i < block.rows(); ++i)
      if (block(i, j) != 0) triplets.emplace_back(global[i], global[j], block(i, j));
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
  F->setZero(layout.size);
  if (J && jacobian_is_zero) {
    ECPSIM_DEMAND(J->rows() == layout.size && J->cols() == layout.size);
  } else if (J) {
    J->setZero(layout.size, layout.size);
  }
  // per body the contact-free Newton–Euler rows, then per contact its rows and its wrenches
  PerBody<StepMotion> bodies(layout.num_bodies);
  for (int b = 0; b < layout.num_bodies; ++b)
    bodies[b] = AddBodyRows(problem.bodies[b], IslandLayout::Velocity(b), z, *F, J);
  const std::vector<StepMotion> kinematic = KinematicMotions(problem);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    AddContactRows(Sides(cp), layout.contacts[k], bodies[cp.body],
                   OtherMotion(cp, bodies, kinematic), problem.h, z, *F, J);
  }
  for (const IslandGripper& g : problem.grippers) ApplyGripperRows(g, problem.bodies, z, *F, J);
}

void EvaluateIslandMncpSparse(const IslandProblem& problem, const IslandLayout& layout,
                              const VectorXd& z, VectorXd* F, Eigen::SparseMatrix<double>* J) {
  F->setZero(layout.size);
  std::vector<Eigen::Triplet<double>> triplets;
  // every diagonal entry is in the pattern (see the header)
  for (int i = 0; i < layout.size; ++i) triplets.emplace_back(i, i, 0.0);
  // per body its Newton–Euler rows on its own ν⁺
  std::vector<StepMotion> bodies;
  Eigen::VectorXd z_local, F_local;
  MatrixXd J_local;
  std::vector<int> global(6);
  for (int b = 0; b < layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    z_local = z.segment<6>(col);
    F_local.setZero(6);
    if (J) J_local.setZero(6, 6);
    StepMotion motion = AddBodyRows(problem.bodies[b], 0, z_local, F_local, J ? &J_local : nullptr);
    motion.column = col;
    bodies.push_back(motion);
    F->segment<6>(col) = F_local;
    if (!J) continue;
    for (int i = 0; i < 6; ++i) global[i] = col + i;
    ScatterNonZeros(J_local, global, triplets);
  }
  // per contact its rows and wrenches on its compact block
  const std::vector<StepMotion> kinematic = KinematicMotions(problem);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const LocalContact local = MakeLocalContact(cp, layout.contacts[k]);
    const int m = static_cast<int>(local.global.size());
    z_local.resize(m);
    for (int i = 0; i < m; ++i) z_local[i] = z[local.global[i]];
    F_local.setZero(m);
    if (J) J_local.setZero(m, m);
    StepMotion body = bodies[cp.body];
    body.column = 0;
    StepMotion other;
    const StepMotion* other_motion = OtherMotion(cp, bodies, kinematic);
    if (other_motion) {
      other = *other_motion;
      other.column = local.other_column;
      other_motion = &other;
    }
    AddContactRows(Sides(cp), local.L, body, other_motion, problem.h, z_local, F_local,
                   J ? &J_local : nullptr);
    // the wrenches add to the bodies' Newton–Euler rows; the contact's own rows are its alone
    for (int i = 0; i < m; ++i) {
      if (i < local.num_body_rows) {
        (*F)[local.global[i]] += F_local[i];
      } else {
        (*F)[local.global[i]] = F_local[i];
      }
    }
    if (J) ScatterNonZeros(J_local, local.global, triplets);
  }
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
        MakeContactFrame(ContactNormalCombination(Sides(cp), L, &other, z), cp.tangent_reference);
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
    return ContactNormalCombination(Sides(cp), layout.contacts[k], nullptr, z);
  StepMotion other;
  other.end = OtherEndPose(problem, z, k);
  return ContactNormalCombination(Sides(cp), layout.contacts[k], &other, z);
}

}  // namespace ecpsim::engine
