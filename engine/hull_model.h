#pragma once
// The paper's model: one MNCP per island for the new velocities, the equivalent contact points on
// the bodies' convex hulls and the contact wrenches with ellipsoidal friction (engine/README.md,
// "The MNCP", "Restart ladder", "Degenerate vertices", "Roots that gain energy").

#include <string>

#include "engine/contact_model.h"
#include "engine/scene.h"

namespace ecpsim::engine {

class HullModel final : public ContactModelStepper {
 public:
  explicit HullModel(const Scene& scene) : scene_(scene) {}
  std::string MessagePrefix() const override { return ""; }
  /// Free flight in closed form when no hull can reach its obstacle within the step; else the
  /// warm start and the restart ladder (plain, then with projected iterates), each with the hull
  /// window grown until the solution holds for the whole hull.
  AdvanceResult Advance(const Island& island, double t, double h,
                        IslandState& state) const override;

 private:
  const Scene& scene_;
};

}  // namespace ecpsim::engine
