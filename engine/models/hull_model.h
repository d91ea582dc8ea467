#pragma once
// The paper's model: one MNCP per island for the new velocities, the equivalent contact points on
// the bodies' convex hulls and the contact wrenches with ellipsoidal friction (engine/README.md,
// "The MNCP", "Restart ladder", "Degenerate vertices", "Roots that gain energy").

#include <string>

#include "engine/contact_model.h"
#include "engine/scene.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

// a contact of an island where bodies touch bodies sticks up to a creep of this fraction of F's
// velocity scale (IslandContact::stick_creep): a held body creeps < 1e-6 m/s at a resting body's
// scale g h; stiffer creeps condition Newton worse and it stalls above the tolerance
// (engine/README.md, "Sticking between bodies")
inline constexpr double kStickCreepFraction = 1e-5;

class HullModel final : public ContactModelStepper {
 public:
  HullModel(const Scene& scene, StepWorkspace& workspace) : scene_(scene), workspace_(workspace) {}
  /// Free flight in closed form when no hull can reach its obstacle within the step; else the
  /// warm start and the restart ladder (plain, then with projected iterates, then with
  /// minimum-norm Newton steps, then with proximal terms), each with the hull window grown until
  /// the solution holds for the whole hull. As the last resort, the ladder's guesses once more
  /// with minimum-norm Newton steps and then proximal terms on the plain iteration and four
  /// times the iteration budget, for steps whose solutions form a set that ends at a degenerate
  /// pair (engine/README.md, "Non-isolated solutions").
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override;
  bool HasLastResort() const override { return true; }

 private:
  const Scene& scene_;
  StepWorkspace& workspace_;
};

}  // namespace ecpsim::engine
