#pragma once
// The multi-convex-patch contact model of Xie & Chakraborty (IDETC 2018): one ECP, wrench and
// complementarity block per convex part of a body, friction about the parts' combined ECP.
// The equations are written out in engine/README.md, "The multi-patch model".

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/contact_model.h"
#include "engine/mncp/mncp_system.h"
#include "engine/models/multipatch_warm_start.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// One body's multi-patch MNCP for one step. `body.contacts` holds one block per (scene contact,
/// part): the part's convex shape (body frame) against the scene contact's obstacle, which must
/// be a half-space; `group[i]` is the scene contact (0-based among this body's contacts) that
/// block i belongs to. The parts of one group share one combined ECP and one sliding velocity.
struct MultiPatchProblem {
  BodyProblem body;
  std::vector<int> group;
  int num_groups = 0;
  // N·s: every part's weight in the combined ECP is max(p_n_i, 0) + weight_floor, so that the
  // combined ECP stays defined while no part carries load (see engine/README.md)
  double weight_floor = 1e-12;
  // the proximal terms of the Newton matrix (AddProximalTerms; engine/README.md, "Non-isolated
  // solutions"): 1/m on each part's ECP along the plane, m/(N·s) on each part's normal impulse
  double ecp_damping = 0;
  double load_damping = 0;
};

/// The layout of `problem`'s multi-patch MNCP: ν⁺, then one block per part, in the plane form
/// (LayOutContacts: a1 free on the plane, no a2, s or l_G unknowns) where the obstacle is a
/// plane, as every multi-patch obstacle is: 5 unknowns a part fewer than MakeLayout's general
/// form (the desk's four feet: 62 unknowns instead of 82). EvaluateMultiPatch takes either.
MncpLayout MakeMultiPatchLayout(const BodyProblem& problem);

/// The contact frame of a block against a half-space (every multi-patch obstacle is one): n the
/// plane's unit normal, t the block's tangent reference projected on the plane, o = n × t.
ContactFrame MultiPatchFrame(const ContactProblem& cp);

/// A part's friction moment about a point `d` (m, world) away from its own ECP along the
/// plane: p_rE = p_r + n · (d × (t p_t + o p_o)) = p_r − p_t o·d + p_o t·d (N·m·s), with d =
/// a1_i − a1 the part's equivalent moment about the combined ECP a1.
double EquivalentMoment(const ContactFrame& frame, const Eigen::Vector3d& d, double p_t, double p_o,
                        double p_r);

/// The combined ECP of group `g`: a1 = Σ w_i a1_i / Σ w_i over the group's blocks, w_i =
/// max(p_n_i, 0) + weight_floor (world frame, m). With `which_a2` the same mean of the a2_i (on
/// a plane, a1_i's projections onto it).
Eigen::Vector3d CombinedEcp(const MultiPatchProblem& problem, const MncpLayout& layout,
                            const Eigen::VectorXd& z, int g, bool which_a2 = false);

/// Residual F(z) and, if `J` is not null, its analytic Jacobian. Rows and unknowns are those of
/// EvaluateMncp on `problem.body` (MakeLayout(problem.body)), except the friction rows of each
/// block i, which are the paper's multi-patch friction model (the IDETC 2018 "friction model for
/// multiple patches"): with the group's combined ECP a1, v_c = v⁺ + ω⁺ × (a1 − c⁺),
/// v_t = t·v_c, v_o = o·v_c, v_r = n·ω⁺, and the equivalent moment about a1
/// p_rE,i = p_r,i + n · ((a1_i − a1) × (t p_t,i + o p_o,i)):
///     e_t² μ p_n,i v_t + p_t,i σ_i = 0,  e_o² μ p_n,i v_o + p_o,i σ_i = 0,
///     e_r² μ p_n,i v_r + p_rE,i σ_i = 0,  0 ≤ σ_i ⊥ μ p_n,i − ‖(p_t,i/e_t, p_o,i/e_o, p_rE,i/e_r)‖
///     ≥ 0.
/// `jacobian_is_zero` as EvaluateMncp's.
void EvaluateMultiPatch(const MultiPatchProblem& problem, const MncpLayout& layout,
                        const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J,
                        bool jacobian_is_zero = false);

/// Adds the proximal terms to `J` (EvaluateMultiPatch's Jacobian at some z) that make the Newton
/// matrix nonsingular on the MNCP's non-isolated solutions: ecp_damping × (I − n nᵀ) to the
/// derivative of each block's normal-cone rows N + Σ l ∇f by its a1 (n the plane's normal), and
/// load_damping to the derivative of its gap row s by its p_n. They are the Jacobian of
/// ecp_damping (I − n nᵀ)(a1 − a1_k) and load_damping (p_n − p_n,k), which vanish at the
/// iterate z_k: a Newton step with them is the step of the proximal-point subproblem at z_k,
/// and F, hence every solution, is unchanged. Zero dampings add nothing, and neither do groups
/// of one block (the hull model's contact, whose solutions are isolated).
void AddProximalTerms(const MultiPatchProblem& problem, const MncpLayout& layout,
                      Eigen::MatrixXd& J);

/// The multi-patch model (ContactModel::kMultiPatch) for islands of one body. A body's parts are
/// Body::parts, or its hull alone when it has none (then the model is the hull model). Each scene
/// contact's ContactState reports the combined solution: a1, a2 the p_n-weighted mean ECPs, p_n,
/// p_t, p_o the sums over the parts, p_r = Σ p_rE,i (the friction moment about a1 along n), σ the
/// p_n-weighted mean of the σ_i; its warm start (MultiPatchWarmStart) holds the parts' unknowns.
class MultiPatchModel final : public ContactModelStepper {
 public:
  MultiPatchModel(const Scene& scene, StepWorkspace& workspace)
      : scene_(scene), workspace_(workspace) {}
  /// Free flight in closed form, else the warm start and the restart ladder (plain, then with
  /// projected iterates).
  /// @throws ModelInvalid if a contact's obstacle is not a half-space.
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override;

 private:
  const Scene& scene_;
  StepWorkspace& workspace_;
};

}  // namespace ecpsim::engine
