#pragma once
// The "usual practice" baseline: contact points at the hull vertices near each obstacle, a
// polyhedral (linearized) friction cone and one linear complementarity problem per step
// (Stewart & Trinkle 1996, Anitescu & Potra 1997), geometrically explicit.

#include <string>

#include "engine/contact_model.h"
#include "engine/scene.h"

namespace ecpsim::engine {

/// Friction directions of the polyhedral cone at each contact point (d unit tangents at equal
/// angles): the cone is inscribed in Coulomb's circle, so sliding friction is under-estimated
/// by up to 1 − cos(π/d) (7.6 % for d = 8) depending on the sliding direction.
constexpr int kPointContactFrictionDirections = 8;

/// The point-contact model (ContactModel::kPointLcp), for islands of one body:
/// - at the start of the step, every hull vertex whose gap ψ to an obstacle (the obstacle's
///   largest constraint value, m) is below an activation distance becomes a contact point with
///   the obstacle's normal at that vertex (explicit geometry: positions of the start of the step);
/// - unknowns v⁺ (6 per body), normal impulses p_n ≥ 0, friction impulses β ≥ 0 (d per point),
///   and a sliding-speed multiplier λ ≥ 0 per point:
///     M (v⁺ − v) = h f_app + Σ (N p_n + D β),
///     0 ≤ p_n ⊥ Nᵀv⁺ + ψ/h ≥ 0,   0 ≤ β ⊥ λ e + Dᵀv⁺ ≥ 0,   0 ≤ λ ⊥ μ p_n − eᵀβ ≥ 0;
///   v⁺ is eliminated and the LCP solved by Lemke's method;
/// - the pose is advanced with v⁺ as in the hull model (p += h v⁺, Q ← Exp(h ω⁺) Q).
/// Friction ellipsoids reduce to Coulomb's μ (torsion comes from the spread of the points).
/// AdvanceResult::iterations counts Lemke pivots; not solved (with what failed: ray termination,
/// pivot limit, a non-finite result) when the LCP has no acceptable solution. The contact states
/// (ContactState) hold the summed normal/friction impulses and their centre of pressure as a1.
class PointContactModel final : public ContactModelStepper {
 public:
  explicit PointContactModel(const Scene& scene) : scene_(scene) {}
  std::string MessagePrefix() const override { return "point model: "; }
  AdvanceResult Advance(const Island& island, double t, double h,
                        IslandState& state) const override;

 private:
  const Scene& scene_;
};

}  // namespace ecpsim::engine
