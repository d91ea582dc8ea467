#pragma once
// The row/unknown scaling of an island's MNCP (FORMULATION.md trap 6) and the units of its
// convergence measure: every body's Newton–Euler rows and ν⁺ in that body's own units
// (mncp_scaling.h), each contact's rows and unknowns in its contact scales.

#include <vector>

#include <Eigen/Core>

#include "engine/mncp/island_mncp.h"
#include "engine/mncp/mncp_scaling.h"

namespace ecpsim::engine {

/// Per island body, BodyScales of its state for the step (a kinematic body has none).
struct IslandScales {
  std::vector<Scales> bodies;
};

/// The units of contact `contact`'s rows and unknowns. Against a fixed or kinematic G: its body
/// F's scales (today's MNCP). Between two dynamic bodies: the smaller of each of the two bodies'
/// length, velocity and impulse — the tighter one. The contact's rows in metres (a1 − a2 − s N,
/// the constraints, the gap) must resolve the smaller hull, or its ECP could sit off its own
/// faces by a fraction of the larger body's size; and an impulse error δp changes each body's
/// velocity by δp / m_b, so it must be small against the lighter body's impulse scale for that
/// body's velocity to be accurate to the tolerance in its own units.
Scales ContactScales(const IslandProblem& problem, const IslandScales& scales, int contact);

/// VariableScales for an island: ν⁺ of body b in its own V and V/L_b, each contact's block in
/// ContactScales. For one body with fixed contacts it is VariableScales to the bit.
Eigen::VectorXd IslandVariableScales(const IslandProblem& problem, const IslandLayout& layout,
                                     const IslandScales& scales);
/// The same into `scale`, whose storage a caller's step after step keeps.
void IslandVariableScales(const IslandProblem& problem, const IslandLayout& layout,
                          const IslandScales& scales, Eigen::VectorXd& scale);

/// RowScales for an island: body b's Newton–Euler rows in 1/P_b and 1/(P_b L_b), each contact's
/// rows in ContactScales. For one body with fixed contacts it is RowScales to the bit.
Eigen::VectorXd IslandRowScales(const IslandProblem& problem, const IslandLayout& layout,
                                const IslandScales& scales);
/// The same into `scale`.
void IslandRowScales(const IslandProblem& problem, const IslandLayout& layout,
                     const IslandScales& scales, Eigen::VectorXd& scale);

/// The units of IslandMncpResidual for a solve with `tolerance`: the bodies' lengths, each
/// contact's ContactScales length, and the largest |coordinate| of the centres of mass (a
/// kinematic body's frame origin) each contact joins at the start of the step.
IslandResidualUnits MakeIslandResidualUnits(const IslandProblem& problem,
                                            const IslandScales& scales, double tolerance);
/// The same into `units`, whose storage a caller's step after step keeps.
void MakeIslandResidualUnits(const IslandProblem& problem, const IslandScales& scales,
                             double tolerance, IslandResidualUnits& units);

/// J: Σ over the island's bodies of EnergyScale, the scale of IslandStepEnergyGain.
double IslandEnergyScale(const IslandProblem& problem, const IslandScales& scales);

}  // namespace ecpsim::engine
