#pragma once
// The planar sliding model of Xie & Chakraborty (WAFR 2018): a body resting flat on a horizontal
// plane, sliding and turning without vertical motion or tipping; a few quadratic equations per
// step. Valid only while the ECP stays inside the support face and p_n > 0.

#include <string>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// The planar sliding model (FORMULATION.md, "The planar-sliding model") for islands of one body
/// on one plane. Unknowns p_t, p_o, p_r, σ; p_n = m g h − p_z (no vertical motion), the ECP at
/// r = ((p_τy − q_z p_t)/p_n, −(q_z p_o + p_τx)/p_n) from the CM projection (zero tipping moment),
/// friction in Fritz-John form with the cone written as μ p_n − ‖p̂‖ (engine/README.md).
class PlanarModel final : public ContactModelStepper {
 public:
  explicit PlanarModel(const Scene& scene) : scene_(scene) {}
  std::string MessagePrefix() const override { return "planar model: "; }
  /// The warm start, then the sliding guess; not solved if neither converges.
  /// @throws ModelInvalid when the model's assumptions fail: the body is not flat on a
  ///         horizontal plane, would lift off (p_n ≤ 0), or its ECP left the support face (it
  ///         would tip).
  AdvanceResult Advance(const Island& island, double t, double h,
                        IslandState& state) const override;

 private:
  const Scene& scene_;
};

}  // namespace ecpsim::engine
