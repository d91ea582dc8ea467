#include "engine/models/balanced_start.h"

#include <cmath>
#include <limits>

#include <Eigen/LU>  // Matrix3d::inverse

#include "engine/mncp/mncp_system.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

// a resting warm start whose contact wrench and ECP the balance would move by at most this
// fraction (of p_n, and of the lever from the CM to the ECP) is taken as unchanged: far above the
// round-off of the Newton–Euler rows' sums (a few ulps of their largest terms), far below any
// change of load a step brings
constexpr double kUnchangedFraction = 1e-12;

// the window positions of the faces that carry contact L in z (multiplier above
// `active_fraction` of the largest), at most kMaxCarrying of them; count −1 where more do
constexpr int kMaxCarrying = 3;
struct Carrying {
  int faces[kMaxCarrying] = {};
  int count = 0;
};
Carrying CarryingFaces(const MncpLayout::Contact& L, double active_fraction, const VectorXd& z) {
  Carrying carrying;
  const double largest = L.l_count > 0 ? z.segment(L.l, L.l_count).maxCoeff() : 0.0;
  if (!(largest > 0)) return carrying;
  for (int i = 0; i < L.l_count; ++i) {
    if (!(z[L.l + i] > active_fraction * largest)) continue;
    if (carrying.count == kMaxCarrying) {
      carrying.count = -1;
      return carrying;
    }
    carrying.faces[carrying.count++] = i;
  }
  return carrying;
}

// the world gradient of window face `position` of contact cp at its ECP a1, the body at `end`
Vector3d FaceNormal(const IslandContact& cp, int position, const EndPose& end, const Vector3d& a1) {
  const Vector3d y = end.R.transpose() * (a1 - end.c);
  return end.R * cp.hull->Gradient(cp.window[position], y);
}

// whether z's contact is the one contact of a body alone, on a plane without creep, pressed
// (p_n > 0) and carried by one hull face: flat (on an edge or a vertex, rocking, the fitted start
// of FitCarryingMultipliers converges as fast: balanced there it took one Newton step more)
bool FlatOnOnePlane(const IslandProblem& problem, const IslandLayout& layout,
                    double active_fraction, const VectorXd& z) {
  if (problem.bodies.size() != 1 || problem.contacts.size() != 1) return false;
  const IslandContact& cp = problem.contacts[0];
  const MncpLayout::Contact& L = layout.contacts[0];
  if (cp.other_kind != Other::kFixed || !L.on_plane() || cp.stick_creep != 0) return false;
  return z[L.p_n] > 0 && CarriedByOneFace(L, active_fraction, z);
}

// the torque rows G(ω⁺) − τ_ext − (a1 − c⁺) × force − n p_r of a body with one contact (G the
// gyroscopic residual, c⁺ = c + h v⁺)
Vector3d TorqueResidual(const BodyProblem& body, const Vector3d& v, const Vector3d& w,
                        const Vector3d& a1, const Vector3d& force, const Vector3d& n, double p_r) {
  return GyroscopicResidual(body, w) - body.p_ext.tail<3>() -
         (a1 - (body.c + body.h * v)).cross(force) - n * p_r;
}

// the plane's contact frame (N is its constant normal)
ContactFrame PlaneFrame(const IslandProblem& problem, const IslandLayout& layout,
                        const VectorXd& z) {
  const IslandContact& cp = problem.contacts[0];
  return MakeContactFrame(ContactNormalCombination(SidesOf(cp), layout.contacts[0], nullptr, z),
                          cp.tangent_reference);
}

// the friction impulse (p_t, p_o, p_r) at maximum dissipation of the slip of (v, ω) at a1 and
// its σ = ‖(e_t v_t, e_o v_o, e_r v_r)‖ (the friction rows e² μ p_n v + p σ = 0 and the cone
// μ p_n = ‖p̂‖ hold with them); the end of the step's CM is c + h v. False where the slip vanishes
bool DissipatingFriction(const BodyProblem& body, const ContactFrame& frame, const Friction& fr,
                         const Vector3d& v, const Vector3d& w, const Vector3d& a1, double p_n,
                         Vector3d& friction, double& slip_norm) {
  const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;
  const Vector3d slip = v + w.cross(a1 - (body.c + body.h * v));
  const double v_t = frame.t.dot(slip), v_o = frame.o.dot(slip), v_r = frame.n.dot(w);
  slip_norm = std::sqrt(et2 * v_t * v_t + eo2 * v_o * v_o + er2 * v_r * v_r);
  if (!(slip_norm > 0)) return false;
  const double mu_pn = fr.mu * p_n;
  friction = Vector3d(-et2 * mu_pn * v_t / slip_norm, -eo2 * mu_pn * v_o / slip_norm,
                      -er2 * mu_pn * v_r / slip_norm);
  return true;
}

}  // namespace

bool CarriedByOneFace(const MncpLayout::Contact& L, double active_fraction, const VectorXd& z) {
  return CarryingFaces(L, active_fraction, z).count == 1;
}

void FitCarryingMultipliers(const IslandProblem& problem, const IslandLayout& layout,
                            double active_fraction, VectorXd& z) {
  if (problem.bodies.size() != 1) return;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const MncpLayout::Contact& L = layout.contacts[k];
    if (cp.other_kind != Other::kFixed) continue;
    const Carrying carrying = CarryingFaces(L, active_fraction, z);
    if (carrying.count < 2) continue;
    const int col = IslandLayout::Velocity(cp.body);
    const EndPose end =
        PoseAfterStep(problem.bodies[cp.body], z.segment<3>(col), z.segment<3>(col + 3));
    const Vector3d a1 = z.segment<3>(L.a1);
    const Vector3d N = ContactNormalCombination(SidesOf(cp), L, nullptr, z);
    Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxCarrying> G(3, carrying.count);
    for (int j = 0; j < carrying.count; ++j) G.col(j) = FaceNormal(cp, carrying.faces[j], end, a1);
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCarrying, 1> fit =
        (G.transpose() * G).ldlt().solve(-G.transpose() * N);
    if (!fit.allFinite() || (fit.array() <= 0).any()) continue;
    for (int j = 0; j < carrying.count; ++j) z[L.l + carrying.faces[j]] = fit[j];
  }
}

bool SweepSlidingBalance(const BodyProblem& body, const ContactFrame& frame, const Friction& fr,
                         double tolerance, AgreeingStart agreeing, SlidingBalance& balance) {
  const Vector3d& n = frame.n;
  const Matrix3d& I = body.inertia_world;

  // the sweeps work on their own copies; `balance` takes them only once they have converged
  Vector3d v = balance.v, w = balance.w, a1 = balance.a1, friction = balance.friction;
  double p_n = balance.p_n;
  double last_change = std::numeric_limits<double>::infinity();
  for (int sweep = 0; sweep < kMaxBalanceSweeps; ++sweep) {
    // friction: maximum dissipation at the slip of the velocities and ECP
    Vector3d next_friction;
    double slip_norm;
    if (!DissipatingFriction(body, frame, fr, v, w, a1, p_n, next_friction, slip_norm))
      return false;
    const double change = (next_friction - friction).norm() / (fr.mu * p_n);
    if (sweep == 0 && agreeing == AgreeingStart::kKeep && change <= tolerance) return false;
    // (the first sweeps settle the start's own mismatch, which may grow once before it shrinks)
    if (sweep > 1 && !(change < last_change)) return false;  // not contracting
    last_change = change;
    friction = next_friction;

    // the force rows m (v⁺ − v) = p_ext + n p_n + t p_t + o p_o: the tangential velocity from
    // them, and p_n from their normal component at the start's normal velocity
    const Vector3d tangential = frame.t * friction[0] + frame.o * friction[1];
    const Vector3d free_v = body.v + (body.p_ext.head<3>() + tangential) / body.mass;
    p_n = body.mass * n.dot(v - free_v);
    if (!(p_n > 0)) return false;
    v = free_v + n * n.dot(v - free_v);

    // the torque rows I (ω⁺ − ω) + h ω⁺ × I ω⁺ − τ_ext − (a1 − c⁺) × force − n p_r = 0: a Newton
    // step on the turn about the face's normal, which leaves it flat, and the ECP's shift in its
    // plane (the gyroscopic term's curvature is left to the next sweeps)
    const Vector3d force = n * p_n + tangential;
    const Vector3d residual = TorqueResidual(body, v, w, a1, force, n, friction[2]);
    // (GyroscopicJacobian's column along n, without the whole matrix)
    const Vector3d Iw = I * w, In = I * n;
    Matrix3d A;  // the residual's derivatives along n (of ω⁺), t and o (of a1)
    A << In + body.h * (w.cross(In) - Iw.cross(n)), force.cross(frame.t), force.cross(frame.o);
    const Vector3d step = -(A.inverse() * residual);
    if (!step.allFinite()) return false;
    w += n * step[0];
    a1 += frame.t * step[1] + frame.o * step[2];
    // (the first sweep's change is the start's friction against its slip, which the sweep's
    // force and torque rows have moved since)
    if (sweep > 0 && change <= tolerance) {
      balance = {v, w, a1, friction, p_n, slip_norm};
      return true;
    }
  }
  return false;
}

StartBalance SweepAndPolish(const BodyProblem& body, const ContactFrame& frame, const Friction& fr,
                            double tolerance, AgreeingStart agreeing, SlidingBalance& balance) {
  if (!SweepSlidingBalance(body, frame, fr, tolerance, agreeing, balance))
    return StartBalance::kUnbalanced;
  // on to the sweeps' own round-off where they still contract there; else the balanced start
  SlidingBalance polished = balance;
  if (!SweepSlidingBalance(body, frame, fr, kPolishTolerance, AgreeingStart::kSweep, polished))
    return StartBalance::kBalanced;
  balance = polished;
  return StartBalance::kPolished;
}

StartBalance BalanceSlidingStart(const IslandProblem& problem, const IslandLayout& layout,
                                 double active_fraction, VectorXd& z) {
  if (!FlatOnOnePlane(problem, layout, active_fraction, z)) return StartBalance::kUnbalanced;
  const MncpLayout::Contact& L = layout.contacts[0];
  if (!(z[L.sigma] > 0)) return StartBalance::kUnbalanced;  // sliding

  const BodyProblem& body = problem.bodies[0];
  const Friction& fr = problem.contacts[0].friction;
  const ContactFrame frame = PlaneFrame(problem, layout, z);  // one for every sweep
  const int col = IslandLayout::Velocity(0);
  SlidingBalance balance{z.segment<3>(col),  z.segment<3>(col + 3),
                         z.segment<3>(L.a1), Vector3d(z[L.p_t], z[L.p_o], z[L.p_r]),
                         z[L.p_n],           z[L.sigma]};
  // a start its friction already agrees with is left as it is: exact where the motion is (a
  // uniform deceleration, which the trend extrapolates exactly), and the sweeps would only move
  // it by their own tolerance
  const StartBalance result =
      SweepAndPolish(body, frame, fr, kBalanceTolerance, AgreeingStart::kKeep, balance);
  if (result == StartBalance::kUnbalanced) return result;
  z.segment<3>(col) = balance.v;
  z.segment<3>(col + 3) = balance.w;
  z.segment<3>(L.a1) = balance.a1;
  z[L.p_t] = balance.friction[0];
  z[L.p_o] = balance.friction[1];
  z[L.p_r] = balance.friction[2];
  z[L.p_n] = balance.p_n;
  z[L.sigma] = balance.slip_norm;
  return result;
}

bool BalanceRestingStart(const IslandProblem& problem, const IslandLayout& layout,
                         double active_fraction, double sticking_slip, VectorXd& z) {
  if (!FlatOnOnePlane(problem, layout, active_fraction, z)) return false;
  const IslandContact& cp = problem.contacts[0];
  const MncpLayout::Contact& L = layout.contacts[0];
  if (!(z[L.sigma] <= sticking_slip)) return false;  // sticking
  const BodyProblem& body = problem.bodies[0];
  const Friction& fr = cp.friction;
  const int col = IslandLayout::Velocity(0);
  const ContactFrame frame = PlaneFrame(problem, layout, z);
  const Vector3d& n = frame.n;
  const Vector3d v = z.segment<3>(col), w = z.segment<3>(col + 3);

  // the force rows m (v⁺ − v) = p_ext + force at z's velocities
  const Vector3d force = body.mass * (v - body.v) - body.p_ext.head<3>();
  const double p_n = n.dot(force), p_t = frame.t.dot(force), p_o = frame.o.dot(force);
  if (!(p_n > 0)) return false;
  // the torque rows I (ω⁺ − ω) + h ω⁺ × I ω⁺ − τ_ext − (a1 − c⁺) × force − n p_r = 0, linear in
  // p_r and the ECP's shift in the face's plane
  Vector3d a1 = z.segment<3>(L.a1);
  const Vector3d residual = TorqueResidual(body, v, w, a1, force, n, z[L.p_r]);
  Matrix3d A;  // the residual's derivatives in p_r and along t and o (of a1)
  A << -n, force.cross(frame.t), force.cross(frame.o);
  const Vector3d step = -(A.inverse() * residual);
  if (!step.allFinite()) return false;
  // loads that did not change leave the warm start as it is (it solves the step already, and
  // the rows' round-off would only move it by an ulp)
  const double lever = (a1 - (body.c + body.h * v)).norm();
  const double unchanged = kUnchangedFraction * p_n;
  if (std::abs(p_n - z[L.p_n]) <= unchanged && std::abs(p_t - z[L.p_t]) <= unchanged &&
      std::abs(p_o - z[L.p_o]) <= unchanged && std::abs(step[0]) <= unchanged * lever &&
      std::hypot(step[1], step[2]) <= kUnchangedFraction * lever)
    return false;
  const double p_r = z[L.p_r] + step[0];
  a1 += frame.t * step[1] + frame.o * step[2];
  // sticking holds only inside the friction ellipsoid
  const double p_hat = std::sqrt(p_t * p_t / (fr.e_t * fr.e_t) + p_o * p_o / (fr.e_o * fr.e_o) +
                                 p_r * p_r / (fr.e_r * fr.e_r));
  if (!(p_hat < fr.mu * p_n)) return false;
  z[L.p_n] = p_n;
  z[L.p_t] = p_t;
  z[L.p_o] = p_o;
  z[L.p_r] = p_r;
  z.segment<3>(L.a1) = a1;
  return true;
}

double BalancedStartTolerance(StartBalance balance, double tolerance) {
  switch (balance) {
    case StartBalance::kUnbalanced:
      return INFINITY;
    case StartBalance::kBalanced:
      return kBalancedStartAcceptance * tolerance;
    case StartBalance::kPolished:
      return kPolishedStartAcceptance * tolerance;
  }
  return INFINITY;
}

}  // namespace ecpsim::engine
