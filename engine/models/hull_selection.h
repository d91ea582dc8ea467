#pragma once
// The selection rule for steps whose solutions form a set (engine/README.md, "Steps whose
// solutions form a set"): among the rigid solutions, the one a vanishing uniform compliance of
// the contact patches picks — the least elastic energy.

#include <Eigen/Core>

#include "engine/islands.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/scene.h"
#include "engine/solver/solution_set.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine::hull {

/// The elastic energy of uniformly compliant contact patches (unit stiffness per area, normal
/// and tangential alike) carrying the impulses of z, as residuals E = ½ |r|²: per contact
/// p_n/√A, p_n e_i/√I_i (the ECP's offset e from the patch's centroid along its principal axes),
/// p_t/√A, p_o/√A and (p_r + n · (e × f))/√(I1 + I2) (the friction moment about the centroid),
/// with each contact's patch and frame taken at z and held fixed (a line or a point contact as a
/// thin patch, geometry::MomentsOf).
EnergyResiduals PatchEnergy(const Scene& scene, const Island& island, const IslandProblem& problem,
                            const IslandLayout& layout, const Eigen::VectorXd& z);

/// What SelectLeastEnergyRoot did.
struct RootSelection {
  bool selected = false;  // z was moved onto the exact problem's set and along it
  int directions = 0;     // the set's dimension at the exact root
  int steps = 0;
};

/// A root `z` of `problem` (solved with its sticking creep) taken onto the exact MNCP's set of
/// solutions (no creep: minimum-norm Newton steps, the nearest root) and along it to the least
/// PatchEnergy; where `last` (the last step's solution laid out as `layout`) is given and is not
/// z, the same from it too (the set may come in pieces no path along it joins), and of the two the
/// one whose loaded contacts all stick inside their friction limits if only one does, else the
/// lesser energy.
/// z is left as it is where neither selection succeeds, or where the selected root gains more
/// energy than the step's allowance (`ejection_energy` as for any root, SolveAttempt).
RootSelection SelectLeastEnergyRoot(const Scene& scene, const Island& island,
                                    const IslandProblem& problem, const IslandLayout& layout,
                                    const IslandScales& scales, double ejection_energy,
                                    double tolerance, StepWorkspace& workspace, Eigen::VectorXd& z,
                                    const Eigen::VectorXd* last = nullptr);

}  // namespace ecpsim::engine::hull
