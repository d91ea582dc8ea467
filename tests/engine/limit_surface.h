#pragma once
// The quasi-static twist of a flat body pushed at a sticking point under the ellipsoidal limit
// surface of the paper's friction (Lynch, Maekawa & Tanie 1992), shared by the pushing tests.
//
// A flat body slides with the twist (v, ω) at its pressure centre, the ECP; the ground's friction
// there is the maximum-dissipation wrench on the ellipsoid with e_t = e_o = 1, e_r = c:
//     f = −μ N v / σ,   τ = −μ N c² ω / σ,   σ = sqrt(|v|² + c² ω²),
// so the twist is ∝ (f_x, f_y, τ / c²). A pusher sticks at P, r = P − ECP, moving at v_p, and
// pushes with F through P. Quasi-static (no inertia): F + f = 0 and (r × F)_z + τ = 0, so
// (r × v)_z = c² ω; sticking: v + ω r⊥ = v_p, r⊥ = ẑ × r. Since (r × v)_z = r⊥ · v,
// v_p = (I + r⊥ r⊥ᵀ / c²) v, and Sherman–Morrison with r⊥ r⊥ᵀ = |r|² I − r rᵀ gives
//     v = (c² v_p + r (r · v_p)) / (c² + |r|²),   ω = (r × v)_z / c² = (r × v_p)_z / (c² + |r|²).

#include <Eigen/Core>

namespace ecpsim::engine::testing {

struct PlanarTwist {
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // m/s, of the body point at the pressure centre
  double w = 0;                                 // rad/s, about z
};

inline Eigen::Vector2d Perp(const Eigen::Vector2d& r) { return {-r.y(), r.x()}; }  // ẑ × r
inline double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// The quasi-static twist of a body pushed at a sticking point at r (m) from its pressure
/// centre, the pusher moving at v_p (m/s), under the friction ellipsoid with e_t = e_o = 1,
/// e_r = c (m): the limit surface's v = (c² v_p + r (r · v_p)) / (c² + |r|²), ω = (r × v)_z / c².
inline PlanarTwist LimitSurfaceTwist(const Eigen::Vector2d& r, const Eigen::Vector2d& v_p,
                                     double c) {
  PlanarTwist twist;
  twist.v = (c * c * v_p + r * r.dot(v_p)) / (c * c + r.squaredNorm());
  twist.w = Cross(r, twist.v) / (c * c);
  return twist;
}

}  // namespace ecpsim::engine::testing
