#pragma once
// The planar sliding model of Xie & Chakraborty (WAFR 2018): a body resting flat on a plane,
// sliding and turning in it without motion along its normal or tipping; a few quadratic
// equations per step. Valid only while the ECP stays inside the support face and p_n > 0.

#include <optional>
#include <string>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// How strictly a planar step checks the model's assumptions (relative to the body's length
/// L = √(tr I / m), in rad for angles).
struct PlanarChecks {
  double flat_angle;      // rad: the support face's normal within this of −N
  double support_length;  // of L: the lowest point on the plane, the ECP on the support face
  double max_rotation;    // rad: the largest turn h|ω⁺| of the step (beyond: not solved)
  // relative: when set, the body must already move in the plane and turn about its normal
  // (|v · N| and |ω × N| L within this of its velocity scale) and N be a principal axis of its
  // inertia (|I_w N × N| within this of N · I_w N), as `model: auto` needs (engine/README.md);
  // unset, those parts of the state are dropped (`model: planar`)
  std::optional<double> in_plane_motion;
};

/// What PlanarStep did: `invalid` names the assumption that failed ("" when the model applies;
/// the state is then untouched); otherwise `result` says whether the solve converged and
/// `face` is the support face (hull face index).
struct PlanarStep {
  std::string invalid;
  AdvanceResult result;
  int face = -1;
};

/// One planar step of an island of one body on one half-space obstacle of any orientation
/// (FORMULATION.md, "The planar-sliding model", written in the plane's frame (t, o, N) of
/// MakeContactFrame(N, TangentReference(N)): the ground's is (x, y, z) to the bit). Unknowns
/// p_t, p_o, p_r, σ; p_n = −(p_applied + m g h)·N (no motion along N); the ECP at
/// r = ((p_τo − q p_t)/p_n, −(q p_o + p_τt)/p_n) from the CM's projection, q the CM's height
/// (zero tipping moment); friction in Fritz-John form with the cone written as μ p_n − ‖p̂‖.
/// Solved from the contact's last impulses, then the sliding guess.
PlanarStep SolvePlanarStep(const Scene& scene, const Island& island, double t, double h,
                           const PlanarChecks& checks, IslandState& state,
                           StepWorkspace& workspace);

/// The planar model as a scene's model (`model: planar`): SolvePlanarStep with checks far below
/// any tilt the hull model would resolve and far above round-off.
class PlanarModel final : public ContactModelStepper {
 public:
  PlanarModel(const Scene& scene, StepWorkspace& workspace)
      : scene_(scene), workspace_(workspace) {}
  /// @throws ModelInvalid when the model's assumptions fail: the body is not flat on a plane,
  ///         would lift off (p_n ≤ 0), or its ECP left the support face (it would tip).
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override;

 private:
  const Scene& scene_;
  StepWorkspace& workspace_;
};

}  // namespace ecpsim::engine
