#pragma once
// Problems for the island MNCP tests: random one-body problems against fixed obstacles with their
// one-body islands (the bit-identity tests), bodies made by hand, and random unknowns for a
// contact.

#include <memory>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/mncp/island_mncp.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/mncp/mncp_system.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine::testing {

/// One body against fixed obstacles, MakeLayout'ed, with random unknowns and scales.
struct RandomBodyCase {
  BodyProblem problem;
  MncpLayout layout;
  Eigen::VectorXd z;
  Scales scales;
};

/// A body of random mass, inertia, pose, velocities and loads (`far`: its CM ~1 km from the
/// origin, where the measure's round-off floor acts), one contact with each obstacle (world frame)
/// whose window is every hull constraint or a random subset of them, and random unknowns of
/// plausible size (positive multipliers, impulses ~ m g h).
inline RandomBodyCase MakeRandomBodyCase(const geometry::ConvexShape& hull,
                                         const std::vector<const geometry::ConvexShape*>& obstacles,
                                         bool far, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const auto vector = [&](double scale) -> Eigen::Vector3d {
    return Eigen::Vector3d(u(rng), u(rng), u(rng)) * scale;
  };
  RandomBodyCase c;
  BodyProblem& p = c.problem;
  p.h = 0.005 + 0.005 * (1 + u(rng));
  p.mass = 2 + u(rng);
  p.R = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized())
            .toRotationMatrix();
  p.inertia_world =
      p.R * (Eigen::Vector3d(0.05, 0.06, 0.07) + vector(0.02)).asDiagonal() * p.R.transpose();
  p.c = vector(far ? 1e3 : 0.5);
  p.v = vector(1);
  p.w = vector(3);
  p.p_gravity = Eigen::Vector3d(0, 0, -9.8 * p.h * p.mass);
  p.p_ext << vector(0.05) + p.p_gravity, vector(0.005);
  for (const geometry::ConvexShape* obstacle : obstacles) {
    ContactProblem cp;
    cp.hull = &hull;
    cp.obstacle = obstacle;
    const bool subset = u(rng) > 0;
    for (int i = 0; i < hull.NumConstraints(); ++i)
      if (!subset || u(rng) > -0.3 || i == 0) cp.window.push_back(i);
    cp.friction = Friction{0.3 + 0.2 * u(rng), 1 + 0.2 * u(rng), 0.8, 0.1 + 0.05 * u(rng)};
    cp.tangent_reference = Eigen::Vector3d(1, 0.5 * u(rng), 0.5 * u(rng)).normalized();
    p.contacts.push_back(cp);
  }
  c.layout = MakeLayout(p);
  c.scales.length = std::sqrt(p.inertia_world.trace() / p.mass);
  c.scales.velocity = 1 + 0.5 * u(rng);
  c.scales.impulse = p.mass * c.scales.velocity;

  const double impulse = p.mass * 9.8 * p.h;
  c.z = Eigen::VectorXd::Zero(c.layout.size);
  c.z.head<3>() = p.v + vector(0.3);
  c.z.segment<3>(3) = p.w + vector(0.3);
  for (const MncpLayout::Contact& L : c.layout.contacts) {
    c.z.segment<3>(L.a1) = p.c + vector(0.1);
    c.z.segment<3>(L.a2) = p.c + vector(0.1);
    c.z[L.s] = 0.01 * u(rng);
    c.z[L.p_t] = 0.3 * impulse * u(rng);
    c.z[L.p_o] = 0.3 * impulse * u(rng);
    c.z[L.p_r] = 0.03 * impulse * u(rng);
    c.z[L.p_n] = impulse * (1 + 0.5 * u(rng));
    c.z[L.sigma] = 0.2 + 0.1 * u(rng);
    for (int i = 0; i < L.l_count; ++i) c.z[L.l + i] = 0.5 + 0.5 * u(rng);
    for (int j = 0; j < L.l_g_count; ++j) c.z[L.l_g + j] = (1 + 0.3 * u(rng)) / L.l_g_count;
  }
  return c;
}

/// A body of 2.5 kg (inertia diag(0.03, 0.05, 0.07) kg·m² in its frame) at c, turned by Q, moving
/// at (v, ω), with gravity's impulse, for a step of 0.01 s; no contacts.
inline BodyProblem MakeMovingBody(const Eigen::Vector3d& c, const Eigen::Quaterniond& Q,
                                  const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  BodyProblem p;
  p.h = 0.01;
  p.mass = 2.5;
  p.R = Q.toRotationMatrix();
  p.inertia_world = p.R * Eigen::Vector3d(0.03, 0.05, 0.07).asDiagonal() * p.R.transpose();
  p.c = c;
  p.v = v;
  p.w = w;
  p.p_gravity = Eigen::Vector3d(0, 0, -9.8 * p.h * p.mass);
  p.p_ext << p.p_gravity, Eigen::Vector3d::Zero();
  return p;
}

/// Random unknowns of plausible size for contact L in z (the Jacobian identities hold at any z):
/// a1 and a2 within 0.02 m of `near`, s within 1 cm, friction impulses up to 0.3 (p_t, p_o) and
/// 0.03 (p_r) times `impulse` (~ m g h), p_n = (1 ± 0.5) impulse, σ = 0.2 ± 0.1, l_i in (0, 1),
/// l_G,j summing to about 1.
inline void RandomizeContact(const MncpLayout::Contact& L, const Eigen::Vector3d& near,
                             double impulse, std::mt19937& rng, Eigen::VectorXd& z) {
  std::uniform_real_distribution<double> u(-1, 1);
  const auto vector = [&](double scale) -> Eigen::Vector3d {
    return Eigen::Vector3d(u(rng), u(rng), u(rng)) * scale;
  };
  z.segment<3>(L.a1) = near + vector(0.02);
  if (!L.on_plane()) {
    z.segment<3>(L.a2) = near + vector(0.02);
    z[L.s] = 0.01 * u(rng);
  }
  z[L.p_t] = 0.3 * impulse * u(rng);
  z[L.p_o] = 0.3 * impulse * u(rng);
  z[L.p_r] = 0.03 * impulse * u(rng);
  z[L.p_n] = impulse * (1 + 0.5 * u(rng));
  z[L.sigma] = 0.2 + 0.1 * u(rng);
  for (int i = 0; i < L.l_count; ++i) z[L.l + i] = 0.5 + 0.5 * u(rng);
  for (int j = 0; j < L.l_g_count; ++j) z[L.l_g + j] = (1 + 0.3 * u(rng)) / L.l_g_count;
}

/// The island of `problem`'s one body with its contacts as fixed obstacles (all of G's
/// constraints, in order): today's MNCP as an island.
inline IslandProblem OneBodyIsland(const BodyProblem& problem) {
  IslandProblem island;
  island.h = problem.h;
  island.bodies.push_back(problem);
  island.bodies[0].contacts.clear();
  for (const ContactProblem& cp : problem.contacts) {
    IslandContact contact;
    contact.body = 0;
    contact.other_kind = IslandContact::Other::kFixed;
    contact.hull = cp.hull;
    contact.window = cp.window;
    contact.other_shape = cp.obstacle;
    for (int j = 0; j < cp.obstacle->NumConstraints(); ++j) contact.other_window.push_back(j);
    contact.friction = cp.friction;
    contact.tangent_reference = cp.tangent_reference;
    island.contacts.push_back(contact);
  }
  return island;
}

}  // namespace ecpsim::engine::testing
