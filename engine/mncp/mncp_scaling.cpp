#include "engine/mncp/mncp_scaling.h"

#include <algorithm>
#include <cmath>

namespace ecpsim::engine {
namespace {

// the velocity scale of a body at rest with nothing acting on it (every quantity of its step is
// then 0, so any nonzero scale will do): a thousandth of its length per step. Not a floor for
// moving bodies: at h = 1e-10 s it would be 2e6 m/s for a 0.2 m body, and a sliding box's
// residuals, measured against it, would pass on the initial guess
constexpr double kRestVelocityLengthsPerStep = 1e-3;
// a body slower than this fraction of its velocity scale counts as at rest (the ladder then starts
// from the resting guess): its slip is far below the sliding guess's resolution
constexpr double kMovingFraction = 1e-3;

}  // namespace

Scales BodyScales(const Body& body, const BodyState& state,
                  const Eigen::Matrix<double, 6, 1>& p_applied, double h) {
  Scales s;
  s.length = std::sqrt(body.inertia.trace() / body.mass);
  const double own = state.v_WB.norm() + state.w_WB.norm() * s.length;
  const double applied =
      p_applied.head<3>().norm() / body.mass + p_applied.tail<3>().norm() / (body.mass * s.length);
  s.velocity = std::max(own, applied);
  if (!(s.velocity > 0)) s.velocity = kRestVelocityLengthsPerStep * s.length / h;
  s.impulse = body.mass * s.velocity;
  return s;
}

Eigen::VectorXd VariableScales(const BodyProblem& problem, const MncpLayout& layout,
                               const Scales& s) {
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(layout.size);
  SetVelocityScales(0, s, scale);
  for (size_t k = 0; k < layout.contacts.size(); ++k)
    SetContactVariableScales(layout.contacts[k], problem.contacts[k].friction, s, scale);
  return scale;
}

Eigen::VectorXd RowScales(const BodyProblem& problem, const MncpLayout& layout, const Scales& s) {
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(layout.size);
  SetNewtonEulerRowScales(0, s, scale);
  for (size_t k = 0; k < layout.contacts.size(); ++k)
    SetContactRowScales(layout.contacts[k], problem.contacts[k].friction, s, scale);
  return scale;
}

void SetVelocityScales(int index, const Scales& s, Eigen::VectorXd& scale) {
  scale.segment<3>(index).setConstant(s.velocity);
  scale.segment<3>(index + 3).setConstant(s.velocity / s.length);
}

void SetContactVariableScales(const MncpLayout::Contact& L, const Friction& friction,
                              const Scales& s, Eigen::VectorXd& scale) {
  scale.segment<3>(L.a1).setConstant(s.length);
  if (!L.on_plane()) scale.segment<4>(L.a2).setConstant(s.length);  // a2, s
  scale[L.p_t] = scale[L.p_o] = scale[L.p_n] = s.impulse;
  scale[L.p_r] = s.impulse * friction.e_r;
  scale[L.sigma] = s.velocity;
}

void SetNewtonEulerRowScales(int index, const Scales& s, Eigen::VectorXd& scale) {
  scale.segment<3>(index).setConstant(1 / s.impulse);
  scale.segment<3>(index + 3).setConstant(1 / (s.impulse * s.length));
}

void SetContactRowScales(const MncpLayout::Contact& L, const Friction& friction, const Scales& s,
                         Eigen::VectorXd& scale) {
  const double e_r = friction.e_r;
  // a1 − a2 − s N (the cone rows, a2's or on a plane a1's, and Σ l_G = 1 are dimensionless)
  scale.segment<3>(L.a1).setConstant(L.on_plane() ? 1 : 1 / s.length);
  scale[L.p_t] = scale[L.p_o] = 1 / (s.impulse * s.velocity);
  scale[L.p_r] = 1 / (s.impulse * s.velocity * e_r);
  scale.segment(L.l, L.l_count).setConstant(1 / s.length);
  scale.segment(L.l_g, L.l_g_count).setConstant(1 / s.length);
  scale[L.p_n] = 1 / s.length;
  scale[L.sigma] = 1 / s.impulse;
}

double EnergyScale(const BodyProblem& problem, const Scales& scales) {
  return problem.mass * scales.velocity * scales.velocity +
         problem.p_ext.head<3>().norm() * scales.length / problem.h;
}

bool IsMoving(const BodyState& state, const Scales& scales) {
  return state.v_WB.norm() + state.w_WB.norm() * scales.length > kMovingFraction * scales.velocity;
}

const char* GuessName(Guess guess) {
  switch (guess) {
    case Guess::kWarm:
      return "warm start";
    case Guess::kSeparated:
      return "separated guess";
    case Guess::kResting:
      return "resting guess";
    case Guess::kSliding:
      return "sliding guess";
    case Guess::kPredicted:
      return "predicted start";
  }
  return "guess";
}

GuessLadder RestartLadder(bool have_warm_start, bool was_in_contact, bool moving) {
  const Guess in_contact = moving ? Guess::kSliding : Guess::kResting;
  const Guess other = moving ? Guess::kResting : Guess::kSliding;
  GuessLadder ladder = {in_contact, other, Guess::kSeparated};
  if (have_warm_start && was_in_contact) {
    ladder.insert(ladder.begin(), Guess::kWarm);
  } else if (have_warm_start) {
    ladder.insert(ladder.begin() + 2, Guess::kWarm);
  }
  return ladder;
}

GuessLadder RestartLadder(bool have_warm_start, const std::vector<ContactState>& contacts,
                          const BodyState& state, const Scales& scales) {
  const bool was_in_contact = std::any_of(contacts.begin(), contacts.end(),
                                          [](const ContactState& c) { return c.p_n > 0; });
  return RestartLadder(have_warm_start, was_in_contact, IsMoving(state, scales));
}

void SetSlidingFriction(const Friction& fr, double p_n, double v_t, double v_o, double v_r,
                        double sigma_floor, const MncpLayout::Contact& L, Eigen::VectorXd& z) {
  const double sigma = std::sqrt(fr.e_t * fr.e_t * v_t * v_t + fr.e_o * fr.e_o * v_o * v_o +
                                 fr.e_r * fr.e_r * v_r * v_r);
  if (!(sigma > sigma_floor)) return;
  z[L.sigma] = sigma;
  z[L.p_t] = -fr.e_t * fr.e_t * fr.mu * p_n * v_t / sigma;
  z[L.p_o] = -fr.e_o * fr.e_o * fr.mu * p_n * v_o / sigma;
  z[L.p_r] = -fr.e_r * fr.e_r * fr.mu * p_n * v_r / sigma;
}

int MostOpposedWindowConstraint(const ContactProblem& cp, const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& y_B, const Eigen::Vector3d& N) {
  return MostOpposedWindowConstraint(*cp.hull, cp.window, R, y_B, N);
}

int MostOpposedWindowConstraint(const geometry::ConvexShape& shape, const std::vector<int>& window,
                                const Eigen::Matrix3d& R, const Eigen::Vector3d& y_B,
                                const Eigen::Vector3d& N) {
  int best = 0;
  double best_alignment = -INFINITY;
  for (int i = 0; i < static_cast<int>(window.size()); ++i) {
    const double alignment = -(R * shape.Gradient(window[i], y_B)).dot(N);
    if (alignment > best_alignment) {
      best_alignment = alignment;
      best = i;
    }
  }
  return best;
}

}  // namespace ecpsim::engine
