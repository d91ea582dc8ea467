#pragma once
// The "usual practice" baseline: contact points at the hull vertices near each obstacle, a
// polyhedral (linearized) friction cone and one linear complementarity problem per step
// (Stewart & Trinkle 1996, Anitescu & Potra 1997), geometrically explicit.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// Friction directions of the polyhedral cone at each contact point (d unit tangents at equal
/// angles): the cone is inscribed in Coulomb's circle, so sliding friction is under-estimated
/// by up to 1 − cos(π/d) (7.6 % for d = 8) depending on the sliding direction.
constexpr int kPointContactFrictionDirections = 8;

/// The point-contact model (ContactModel::kPoint), for islands of one or more dynamic bodies:
/// - at the start of the step, every hull vertex whose gap ψ to an obstacle (the obstacle's
///   largest constraint value, m) is below an activation distance becomes a contact point with
///   the obstacle's normal at that vertex (explicit geometry: positions of the start of the step);
///   between two bodies F and G (kinematic or dynamic) both ways: F's vertices near G's hull with
///   G's face normal, and G's vertices near F's hull with F's (reversed), the normal always
///   pointing from G into F;
/// - unknowns ν⁺ (6 per dynamic body of the island), normal impulses p_n ≥ 0, friction impulses
///   β ≥ 0 (d per point), and a sliding-speed multiplier λ ≥ 0 per point:
///     M (ν⁺ − ν) = h f_app + Σ (N p_n + D β),
///     0 ≤ p_n ⊥ Nᵀν⁺ − n·v_G + ψ/h ≥ 0,   0 ≤ β ⊥ λ e + Dᵀν⁺ − D·v_G ≥ 0,
///     0 ≤ λ ⊥ μ p_n − eᵀβ ≥ 0;
///   a point's impulse acts on F and its opposite on G when G is dynamic (N and D hold both
///   bodies' blocks); v_G is a kinematic G's prescribed velocity at the point (its StepTwist);
///   ν⁺ is eliminated and the LCP solved by Lemke's method;
/// - the pose is advanced with ν⁺ as in the hull model (p += h v⁺, Q ← Exp(h ω⁺) Q).
/// Friction ellipsoids reduce to Coulomb's μ (torsion comes from the spread of the points).
/// AdvanceResult::iterations counts Lemke pivots; not solved (with what failed: ray termination,
/// pivot limit, a non-finite result) when the LCP has no acceptable solution. The contact states
/// (ContactState) hold the summed impulses on F, their centre of pressure as a1 and its
/// projection on G as a2.
class PointModel final : public ContactModelStepper {
 public:
  /// Per scene body, per side a contact can touch: [0] its hull's vertices, [1 + i] part i's (a
  /// smooth shape's from its tessellation), body frame.
  using SideVertices = std::vector<std::vector<std::vector<Eigen::Vector3d>>>;

  /// Keeps references to `scene` and `workspace` (they must outlive the model) and each body's
  /// hull and parts' vertices.
  PointModel(const Scene& scene, StepWorkspace& workspace);
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override;

 private:
  const Scene& scene_;
  StepWorkspace& workspace_;
  SideVertices vertices_;
};

}  // namespace ecpsim::engine
