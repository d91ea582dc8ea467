#pragma once
// The paper's model: one MNCP per island for the new velocities, the equivalent contact points on
// the bodies' convex hulls and the contact wrenches with ellipsoidal friction (engine/README.md,
// "The MNCP", "Restart ladder", "Degenerate vertices", "Roots that gain energy").

#include <string>

#include "engine/contact_model.h"
#include "engine/scene.h"

namespace ecpsim::engine {

// a contact of an island where bodies touch bodies sticks up to a creep of this fraction of F's
// velocity scale (IslandContact::stick_creep): a held body creeps < 1e-6 m/s at the scale g h of
// a resting body (0.098 m/s at h = 0.01 s), 1e-5 m in 10 s, and the friction it makes unique is
// resolved to the solver's tolerance over it, 1e-7 of e² μ p_n. Stiffer creeps condition Newton
// worse, and it stalls 100–1000 × above the tolerance: examples/push_sweep.py's 1,000 runs (seed
// 1) failed 61 times at 1e-7, 20 at 1e-6, once here (none since the last resort), while the 939
// runs every one completed ended as close to each other at 1e-5 as at 1e-6 (median 0.4 mm, 90 %
// within 5 mm of the 1e-7 poses after 1 s: the point push's own sensitivity, not the creep's
// ≤ 3 µm of slip) (engine/README.md)
inline constexpr double kStickCreepFraction = 1e-5;

class HullModel final : public ContactModelStepper {
 public:
  explicit HullModel(const Scene& scene) : scene_(scene) {}
  std::string MessagePrefix() const override { return ""; }
  /// Free flight in closed form when no hull can reach its obstacle within the step; else the
  /// warm start and the restart ladder (plain, then with projected iterates, then with
  /// minimum-norm Newton steps), each with the hull window grown until the solution holds for
  /// the whole hull.
  AdvanceResult Advance(const Island& island, double t, double h,
                        IslandState& state) const override;
  /// The ladder's guesses once more with minimum-norm Newton steps on the plain iteration and
  /// four times the iteration budget, for steps whose solutions form a set that ends at a
  /// degenerate pair (engine/README.md, "Non-isolated solutions").
  std::optional<AdvanceResult> AdvanceAsLastResort(const Island& island, double t, double h,
                                                   IslandState& state) const override;

 private:
  const Scene& scene_;
};

}  // namespace ecpsim::engine
