#pragma once
// The hull model's re-solves of a stalled attempt: Newton stalls just above the tolerance where
// faces are weakly active at the root, where four or more hull faces meet at the ECP, or on the
// fold of an edge's moment balance; the faces that carry the contact alone, one face left out,
// or starts along the edge solve it (engine/README.md, "Degenerate vertices", "Stalls on an
// edge", "Which stalls are re-solved").
//
// Each re-solve takes the stalled problem, its layout and iterate `z`, the solver's `options`,
// the bodies' scales and the ejection energy allowed (as SolveAttempt), and commits an accepted
// root into `state` (AcceptReduced), adding its solves' iterations to `result`.

#include <vector>

#include <Eigen/Core>

#include "engine/contact_model.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/models/hull_attempt.h"
#include "engine/models/hull_tuning.h"
#include "engine/solver/complementarity_solver.h"

namespace ecpsim::engine::hull {

/// Whether a stalled attempt may be a degenerate vertex's, weakly active faces' or an edge's
/// stall: within kMaxOneBodyStall of `tolerance` in an island of one body, within
/// kMaxDegenerateStall in one of several. Far above, the iterate is no root's neighbour, its
/// multipliers are arbitrary, and each re-solve (a whole island solve) only adds cost.
bool IsNearSolutionStall(const IslandLayout& layout, const Attempt& attempt, double tolerance);

/// The re-solves in turn: SolveOnCarryingFaces, SolveAtDegenerateVertex, SolveAlongCarryingEdge;
/// true once one is committed. Each accepted root goes through `select` first (AcceptReduced).
bool ReSolveStall(const IslandProblem& problem, const IslandLayout& layout,
                  const Eigen::VectorXd& z, McpOptions& options, const IslandScales& scales,
                  double ejection_energy, StepWorkspace& workspace, IslandState& state,
                  AdvanceResult& result, const RootSelector& select = {});

/// The positions among z's `count` multipliers from `first` on that carry the contact: above
/// kCarryingFraction of the largest.
std::vector<int> Carrying(const Eigen::VectorXd& z, int first, int count);

/// The contact whose rows (measured as in the convergence measure, without its round-off floor)
/// hold the largest residual at `z`.
int StalledContact(const IslandProblem& problem, const IslandLayout& layout,
                   const Eigen::VectorXd& z, const IslandScales& scales);

/// Re-solves from `z` with each of F's windows, and a moving G's, cut to the constraints that
/// carry the contact (Carrying): without the weakly active ones the reduced problem's pairs are
/// no longer degenerate. False where no window would be cut.
bool SolveOnCarryingFaces(const IslandProblem& problem, const IslandLayout& layout,
                          const Eigen::VectorXd& z, McpOptions& options, const IslandScales& scales,
                          double ejection_energy, StepWorkspace& workspace, IslandState& state,
                          AdvanceResult& result, const RootSelector& select = {});

/// Where four or more hull faces meet at the ECP their multipliers are not unique and their
/// merged planes meet only up to the merge tolerance: the support is one of the tiny vertices
/// where three meet, and Newton stalls between them. Re-solves from `z` with each of the
/// contact's active faces (above kDegenerateActiveFraction of the largest multiplier) left out
/// of F's window in turn, smallest multipliers first; a reduced problem that stalls again at
/// four leaves out one more, up to `depth` faces in all. In an island of several bodies only the
/// StalledContact is tried: the tree of every contact's drops grows as their count to the power
/// `depth`.
bool SolveAtDegenerateVertex(const IslandProblem& problem, const IslandLayout& layout,
                             const Eigen::VectorXd& z, McpOptions& options,
                             const IslandScales& scales, double ejection_energy,
                             StepWorkspace& workspace, IslandState& state, AdvanceResult& result,
                             int depth = kMaxDegenerateDrops, const RootSelector& select = {});

/// A body that slides and spins on an edge, its ECP near the centre of rotation, has a moment
/// balance that is not monotone in the ECP's place along the edge, and Newton can end on the fold
/// (a local minimum of the merit function). Re-solves a contact carried by two faces from
/// kEdgeStarts places along their edge over the hull's extent, nearest first, each from the
/// stalled iterate and from each carrying face's own root. Every contact of a body alone is
/// tried; in an island of several bodies the StalledContact.
bool SolveAlongCarryingEdge(const IslandProblem& problem, const IslandLayout& layout,
                            const Eigen::VectorXd& z, McpOptions& options,
                            const IslandScales& scales, double ejection_energy,
                            StepWorkspace& workspace, IslandState& state, AdvanceResult& result,
                            const RootSelector& select = {});

}  // namespace ecpsim::engine::hull
