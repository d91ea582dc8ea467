#include "engine/models/hull_guesses.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "engine/mncp/mncp_system.h"
#include "engine/models/hull_problem.h"
#include "engine/models/hull_tuning.h"
#include "engine/models/hull_warm_start.h"
#include "engine/models/solution_trend.h"
#include "engine/obstacle_queries.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

// contact k's point extrapolated along its trend to the end of this step, if it has one for
// steps of this length
std::optional<SolutionTrend::Point> PredictedPoint(const IslandProblem& problem,
                                                   const IslandState& state, int k) {
  const auto* warm = state.contacts[k].warm_start.Get<HullWarmStart>();
  if (warm == nullptr) return std::nullopt;
  const BodyState& body = state.bodies[problem.contacts[k].body];
  return PredictPoint(warm->trend, TrendPoint(body, state.contacts[k], warm->s), problem.h);
}

// the predicted start's unknowns of contact k over its warm start's, with its body's velocity
// (every contact of the body carries the same trend of it); the complementarity unknowns kept
// ≥ 0, the multipliers l and l_G the warm start's (a face's multiplier follows no trend)
void SetPredicted(const IslandProblem& problem, const IslandLayout& layout,
                  const IslandState& state, int k, VectorXd& z) {
  const std::optional<SolutionTrend::Point> point = PredictedPoint(problem, state, k);
  if (!point) return;
  const MncpLayout::Contact& L = layout.contacts[k];
  z.segment<6>(IslandLayout::Velocity(problem.contacts[k].body)) = point->head<6>();
  z.segment<3>(L.a1) = point->segment<3>(6);
  if (!L.on_plane()) {
    z.segment<3>(L.a2) = point->segment<3>(9);
    z[L.s] = std::max((*point)[12], 0.0);
  }
  z[L.p_n] = std::max((*point)[13], 0.0);
  z[L.p_t] = (*point)[14];
  z[L.p_o] = (*point)[15];
  z[L.p_r] = (*point)[16];
  z[L.sigma] = std::max((*point)[17], 0.0);
}

// each island body's end pose under its last velocities (PoseAfterStep)
std::vector<EndPose> LastMotionEndPoses(const IslandProblem& problem, const IslandState& state) {
  std::vector<EndPose> poses;
  poses.reserve(problem.bodies.size());
  for (size_t b = 0; b < problem.bodies.size(); ++b)
    poses.push_back(PoseAfterStep(problem.bodies[b], state.bodies[b].v_WB, state.bodies[b].w_WB));
  return poses;
}

// contact k's last ECPs carried to the end of this step with their bodies (each point fixed in
// its body, the body at `end_poses`, a kinematic G at its prescribed end pose)
void CarryPoints(const IslandProblem& problem, const IslandState& state,
                 const std::vector<EndPose>& end_poses, int k, const MncpLayout::Contact& L,
                 VectorXd& z) {
  const IslandContact& cp = problem.contacts[k];
  const auto carry = [&](int b, const Vector3d& a) -> Vector3d {
    const BodyProblem& body = problem.bodies[b];
    return end_poses[b].c + end_poses[b].R * (body.R.transpose() * (a - body.c));
  };
  const ContactState& previous = state.contacts[k];
  z.segment<3>(L.a1) = carry(cp.body, previous.a1);
  if (L.on_plane()) return;
  if (cp.other_kind == Other::kBody) {
    z.segment<3>(L.a2) = carry(cp.other, previous.a2);
  } else if (cp.other_kind == Other::kKinematic) {
    const KinematicBody& g = problem.kinematic[cp.other];
    const EndPose end = PoseAfterStep(g.c, g.R, problem.h, g.v, g.w);
    z.segment<3>(L.a2) = end.c + end.R * (g.R.transpose() * (previous.a2 - g.c));
  }
}

}  // namespace

bool AnyBodyMoving(const IslandState& state, const IslandScales& scales) {
  bool moving = false;
  for (size_t i = 0; i < state.bodies.size(); ++i)
    moving |= IsMoving(state.bodies[i], scales.bodies[i]);
  return moving;
}

GuessLadder HullLadder(const IslandProblem& problem, const IslandState& state,
                       const IslandScales& scales, bool moving) {
  const bool have_warm_start =
      state.contacts.empty() || (state.contacts[0].warm_start.Get<HullWarmStart>() != nullptr);
  const bool was_in_contact = std::any_of(state.contacts.begin(), state.contacts.end(),
                                          [](const ContactState& c) { return c.p_n > 0; });
  GuessLadder ladder = RestartLadder(have_warm_start, was_in_contact, moving);
  // a body landing on another feature of its hull: the sliding guess first
  if (moving && ladder.front() == Guess::kWarm && Lands(problem, state, scales)) {
    ladder.erase(std::find(ladder.begin(), ladder.end(), Guess::kSliding));
    ladder.insert(ladder.begin(), Guess::kSliding);
  }
  // a body alone, moving in contact along a trend of steps of this length: the warm start
  // extrapolated along it first
  if (ladder.front() == Guess::kWarm && moving && Predictable(problem, state, scales))
    ladder.insert(ladder.begin(), Guess::kPredicted);
  return ladder;
}

int StallIterations(Guess guess, bool first_pass, bool plain_newton, std::size_t num_bodies) {
  if (plain_newton) return 0;
  if (guess == Guess::kPredicted) return kPredictedStallIterations;
  if (first_pass && guess == Guess::kWarm && num_bodies == 1) return kWarmStartStallIterations;
  return kStallIterations;
}

bool MayFlyFree(const IslandProblem& problem, const IslandState& state) {
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    if (cp.other_kind != Other::kFixed) continue;
    if (!cp.other_shape->IsHalfSpace()) return false;
    const BodyProblem& body = problem.bodies[cp.body];
    const EndPose pose = PoseAfterStep(body, body.free.v, body.free.w);
    const Vector3d& n = state.contacts[k].n;
    const Vector3d a1 = WorldSupport(*cp.hull, pose.c, pose.R, -n);
    if (!(cp.other_shape->Value(0, a1) > 0)) return false;
  }
  return true;
}

bool AllContactsApart(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                      const IslandState& state) {
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const MncpLayout::Contact& L = layout.contacts[k];
    if (cp.other_kind == Other::kFixed) {
      if (!cp.other_shape->IsHalfSpace()) return false;
      if (!(cp.other_shape->Value(0, z.segment<3>(L.a1)) > 0)) return false;
    } else if (!(state.contacts[k].n.dot(z.segment<3>(L.a1) - z.segment<3>(L.a2)) > 0)) {
      return false;
    }
  }
  return true;
}

bool Lands(const IslandProblem& problem, const IslandState& state, const IslandScales& scales) {
  if (problem.bodies.size() != 1 || problem.contacts.size() != 1) return false;
  const IslandContact& cp = problem.contacts[0];
  const ContactState& last = state.contacts[0];
  if (cp.other_kind != Other::kFixed || !(last.p_n > 0)) return false;
  const BodyProblem& body = problem.bodies[0];
  const EndPose end = PoseAfterStep(body, state.bodies[0].v_WB, state.bodies[0].w_WB);
  const Vector3d deepest = WorldSupport(*cp.hull, end.c, end.R, -last.n);
  const Vector3d ecp = end.c + end.R * (body.R.transpose() * (last.a1 - body.c));
  return last.n.dot(ecp - deepest) > kLandingDip * scales.bodies[0].length;
}

bool AloneOnFixedObstacles(const IslandProblem& problem) {
  return problem.bodies.size() == 1 && !problem.contacts.empty() &&
         std::all_of(problem.contacts.begin(), problem.contacts.end(),
                     [](const IslandContact& cp) { return cp.other_kind == Other::kFixed; });
}

bool CarriesPoints(const IslandProblem& problem, const IslandState& state,
                   const IslandScales& scales) {
  return !AloneOnFixedObstacles(problem) && AnyBodyMoving(state, scales);
}

bool Predictable(const IslandProblem& problem, const IslandState& state,
                 const IslandScales& scales) {
  if (!AloneOnFixedObstacles(problem)) return false;
  const double L = scales.bodies[0].length;
  const auto speed = [L](const SolutionTrend::Point& d) {
    return d.head<3>().norm() + d.segment<3>(3).norm() * L;
  };
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const auto* warm = state.contacts[k].warm_start.Get<HullWarmStart>();
    if (warm == nullptr || !Predicts(warm->trend, problem.h)) return false;
    const SolutionTrend& trend = warm->trend;
    const double bend = speed(trend.second);
    if (!(bend <= kMaxTrendBend * speed(trend.first) ||
          bend <= kNegligibleBend * scales.bodies[0].velocity))
      return false;
  }
  return true;
}

VectorXd MakeGuess(Guess guess, const Vector3d& gravity, IslandProblem& problem,
                   const IslandLayout& layout, const IslandState& state,
                   const IslandScales& scales) {
  VectorXd z = VectorXd::Zero(layout.size);
  // free-flight velocities as the starting point of a fresh guess; the last ones for warm starts
  const bool from_last = guess == Guess::kWarm || guess == Guess::kPredicted;
  const bool carry_points = guess == Guess::kWarm && CarriesPoints(problem, state, scales);
  const std::vector<EndPose> end_poses =
      carry_points ? LastMotionEndPoses(problem, state) : std::vector<EndPose>();
  for (int b = 0; b < layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    const auto& [v_free, w_free] = problem.bodies[b].free;
    z.segment<3>(col) = from_last ? state.bodies[b].v_WB : v_free;
    z.segment<3>(col + 3) = from_last ? state.bodies[b].w_WB : w_free;
  }

  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    IslandContact& cp = problem.contacts[k];
    const MncpLayout::Contact& L = layout.contacts[k];
    const ContactState& previous = state.contacts[k];
    const Friction& fr = cp.friction;
    const BodyProblem& body = problem.bodies[cp.body];
    const int col = IslandLayout::Velocity(cp.body);
    cp.tangent_reference = TangentReference(previous.n);
    const double sigma0 = kInitialSigmaFraction * scales.bodies[cp.body].velocity;

    const auto* warm = previous.warm_start.Get<HullWarmStart>();
    if (from_last && warm != nullptr) {
      z.segment<3>(L.a1) = previous.a1;
      if (!L.on_plane()) {
        z.segment<3>(L.a2) = previous.a2;
        z[L.s] = warm->s;
      }
      if (carry_points) CarryPoints(problem, state, end_poses, static_cast<int>(k), L, z);
      z[L.p_t] = previous.p_t;
      z[L.p_o] = previous.p_o;
      z[L.p_r] = previous.p_r;
      z[L.p_n] = previous.p_n;
      z[L.sigma] = previous.sigma;
      if (guess == Guess::kPredicted) SetPredicted(problem, layout, state, static_cast<int>(k), z);
      // (on a plane l_G = 1 is no unknown)
      if (cp.other_kind != Other::kFixed) {
        CarryByFace(warm->other_window, warm->l_g, 0, cp.other_window, z, L.l_g);
      } else if (!L.on_plane()) {
        z.segment(L.l_g, L.l_g_count) = warm->l_g;
      }
      // carry hull multipliers over by face index (the window may have moved); windows are
      // sorted (SelectWindow), so a binary search does it without building a map every step
      const std::vector<int>& window = warm->window;
      for (int i = 0; i < L.l_count; ++i) {
        const auto it = std::lower_bound(window.begin(), window.end(), cp.window[i]);
        if (it != window.end() && *it == cp.window[i]) z[L.l + i] = warm->l[it - window.begin()];
      }
      continue;
    }

    // geometric guess at the free-flight poses: F's support point in the direction −n
    const Vector3d n = previous.n;
    const EndPose pose = PoseAfterStep(body, z.segment<3>(col), z.segment<3>(col + 3));
    const Vector3d support = WorldSupport(*cp.hull, pose.c, pose.R, -n);
    // a contact without a warm start (new to the ladder) starts as separated
    const bool separated = guess == Guess::kSeparated || guess == Guess::kWarm;
    Vector3d a1 = support;
    if (!separated) a1 = pose.c - n * n.dot(pose.c - support);  // under the CM
    Vector3d a2, N;
    Vector3d v_other = Vector3d::Zero();  // G's velocity at the contact, for the sliding guess
    if (cp.other_kind == Other::kFixed) {
      const auto [projection, active_g] = ProjectOntoObstacle(*cp.other_shape, a1);
      a2 = projection;
      if (!L.on_plane()) z[L.l_g + active_g] = 1;
      N = cp.other_shape->Gradient(active_g, a2);
    } else {
      // G's support point in +n at its end pose, and a1 on its support plane when touching
      const EndPose other = OtherEndPose(problem, z, static_cast<int>(k));
      const Vector3d top = WorldSupport(*cp.other_shape, other.c, other.R, n);
      a2 = separated ? top : Vector3d(a1 - n * n.dot(a1 - top));
      const Vector3d y_g = other.R.transpose() * (a2 - other.c);
      // G's window constraint whose world normal is most aligned with n carries its cone
      const int best_g =
          MostOpposedWindowConstraint(*cp.other_shape, cp.other_window, other.R, y_g, -n);
      z[L.l_g + best_g] = 1;
      N = other.R * cp.other_shape->Gradient(cp.other_window[best_g], y_g);
      if (cp.other_kind == Other::kKinematic) {
        const KinematicBody& g = problem.kinematic[cp.other];
        v_other = g.v + g.w.cross(a2 - other.c);
      } else {
        const int other_col = IslandLayout::Velocity(cp.other);
        v_other =
            z.segment<3>(other_col) + Vector3d(z.segment<3>(other_col + 3)).cross(a2 - other.c);
      }
    }
    z.segment<3>(L.a1) = a1;
    if (!L.on_plane()) {
      z.segment<3>(L.a2) = a2;
      z[L.s] = separated ? std::max(0.0, (a1 - a2).dot(N) / N.squaredNorm()) : 0;
    }
    // the window face whose world normal is most opposed to N carries the cone
    const Vector3d y = pose.R.transpose() * (a1 - pose.c);
    const int best = MostOpposedWindowConstraint(*cp.hull, cp.window, pose.R, y, N);
    z[L.l + best] = 1;
    z[L.sigma] = sigma0;
    if (separated) continue;

    // in contact: the normal impulse that cancels gravity and the approach velocity
    const Vector3d& v_start = state.bodies[cp.body].v_WB;
    double p_n = 0;
    Vector3d v_tangent;
    if (cp.other_kind == Other::kFixed) {
      p_n = std::max(body.mass * (-n.dot(z.segment<3>(col))), 0.0) +
            std::max(-body.mass * gravity.dot(n) * problem.h, 0.0);
      v_tangent = v_start - n * n.dot(v_start);
    } else {
      // F and G end the step with a common normal velocity: G's own when kinematic, the
      // momentum-weighted mean of the two when G is a body (a perfectly inelastic impact)
      double v_common = n.dot(v_other);
      if (cp.other_kind == Other::kBody) {
        const double m_g = problem.bodies[cp.other].mass;
        const int other_col = IslandLayout::Velocity(cp.other);
        v_common = (body.mass * n.dot(z.segment<3>(col)) + m_g * n.dot(z.segment<3>(other_col))) /
                   (body.mass + m_g);
        const Vector3d v_g = z.segment<3>(other_col);
        z.segment<3>(other_col) = v_g - n * (n.dot(v_g) - v_common);
      }
      p_n = std::max(body.mass * (v_common - n.dot(z.segment<3>(col))), 0.0) +
            std::max(-body.mass * gravity.dot(n) * problem.h, 0.0);
      const Vector3d v_f = z.segment<3>(col);
      v_tangent = v_f - n * (n.dot(v_f) - v_common);
    }
    z[L.p_n] = p_n;
    z.segment<3>(col) = v_tangent;
    if (guess == Guess::kSliding) {
      const ContactFrame frame = MakeContactFrame(N, cp.tangent_reference);
      const Vector3d slip = v_tangent - v_other;
      const double v_t = frame.t.dot(slip), v_o = frame.o.dot(slip);
      const double v_r = frame.n.dot(state.bodies[cp.body].w_WB);
      SetSlidingFriction(fr, p_n, v_t, v_o, v_r, sigma0, L, z);
    }
  }
  return z;
}

StartBalance BalanceGuess(Guess guess, bool moving, const IslandProblem& problem,
                          const IslandLayout& layout, const IslandScales& scales, VectorXd& z) {
  if (guess == Guess::kPredicted)
    FitCarryingMultipliers(problem, layout, kDegenerateActiveFraction, z);
  if (moving) {
    if (guess != Guess::kPredicted && guess != Guess::kWarm && guess != Guess::kSliding)
      return StartBalance::kUnbalanced;
    return BalanceSlidingStart(problem, layout, kDegenerateActiveFraction, z);
  }
  return guess == Guess::kWarm && !scales.bodies.empty() &&
                 BalanceRestingStart(problem, layout, kDegenerateActiveFraction,
                                     kStickingSlipFraction * scales.bodies[0].velocity, z)
             ? StartBalance::kBalanced
             : StartBalance::kUnbalanced;
}

}  // namespace ecpsim::engine::hull
