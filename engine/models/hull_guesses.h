#pragma once
// The hull model's starts: the restart ladder's guesses and their order, free flight in closed
// form, and the balance that makes a guess consistent with the step's equations (engine/README.md,
// "Restart ladder", "The predicted start", "Landings", "Balanced starts").

#include <cstddef>

#include <Eigen/Core>

#include "engine/contact_model.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/models/balanced_start.h"

namespace ecpsim::engine::hull {

/// Whether any body of the island moves (IsMoving at its scales).
bool AnyBodyMoving(const IslandState& state, const IslandScales& scales);

/// The guesses of the island's step in the order they are tried: RestartLadder's, with the
/// sliding guess first where a moving body lands on another feature of its hull (Lands), and
/// the predicted start before the warm start where a moving body follows a trend (Predictable).
GuessLadder HullLadder(const IslandProblem& problem, const IslandState& state,
                       const IslandScales& scales, bool moving);

/// The solver's stall budget (McpOptions::stall_iterations) for `guess`: none on the plain
/// Newton iteration, the shortest for the predicted start, a shorter one for a body alone's warm
/// start in the first pass (later guesses take its stall over), else kStallIterations.
int StallIterations(Guess guess, bool first_pass, bool plain_newton, std::size_t num_bodies);

/// AllContactsApart's answer for the separated guess where a fixed G decides it, without
/// building the guess: false if a fixed contact's hull, at the free-flight end pose, does not
/// end strictly outside its half-space (its support point in −n, as MakeGuess computes the
/// separated guess's a1) or its G is no half-space; true where that does not decide it. A body
/// on the ground fails here at the cost of one support point.
bool MayFlyFree(const IslandProblem& problem, const IslandState& state);

/// Whether every contact's G is apart from the separated guess's a1 (F's support point in −n
/// at the free-flight end pose): a half-space obstacle strictly below a1, a moving G whose
/// support point a2 in +n lies strictly behind a1 along n (the plane normal to n between them
/// separates the hulls). Any other obstacle: false. Where true, `z` solves the MNCP exactly.
bool AllContactsApart(const IslandProblem& problem, const IslandLayout& layout,
                      const Eigen::VectorXd& z, const IslandState& state);

/// Whether a body alone on one fixed obstacle lands in this step on another part of its hull
/// than the one it touched: at the end pose of its last velocities, a hull point goes deeper
/// along the contact's normal than the last ECP (carried with the body) by kLandingDip of its
/// length. Rocking on an edge or a vertex keeps the ECP the deepest point.
bool Lands(const IslandProblem& problem, const IslandState& state, const IslandScales& scales);

/// Whether the island is one body whose every contact is with a fixed obstacle (the islands
/// the predicted start is for).
bool AloneOnFixedObstacles(const IslandProblem& problem);

/// Whether the warm start carries the last ECPs with their bodies (MakeGuess): where the island
/// moves and is not a body alone on fixed obstacles. The last ECPs lie where the bodies were at
/// the end of the last step; a body moving at v takes its contact points h v further in this
/// one (a row of pushed boxes: the uncarried start's residual 1.4e-2, the carried one's at
/// round-off). A body alone on fixed obstacles has the predicted start instead, which
/// extrapolates its points along their trend.
bool CarriesPoints(const IslandProblem& problem, const IslandState& state,
                   const IslandScales& scales);

/// Whether the predicted start applies: one body against fixed obstacles, every contact with a
/// trend for steps of this length whose second difference is small (kMaxTrendBend of its first,
/// or kNegligibleBend of the velocity scale).
bool Predictable(const IslandProblem& problem, const IslandState& state,
                 const IslandScales& scales);

/// The unknowns of `guess` laid out as `layout`: the last step's solution (warm, its ECPs carried
/// with their bodies where CarriesPoints; predicted), or
/// a geometric guess at the free-flight poses (separated, resting, sliding) with the normal
/// impulse that cancels gravity (`gravity`, m/s²) and the approach velocity. Sets each
/// contact's tangent reference in `problem`.
Eigen::VectorXd MakeGuess(Guess guess, const Eigen::Vector3d& gravity, IslandProblem& problem,
                          const IslandLayout& layout, const IslandState& state,
                          const IslandScales& scales);

/// The guess `z` made consistent with the step's equations where balanced_start.h can: the
/// predicted start, the warm start or the sliding guess of a moving body (a predicted start's
/// carrying multipliers fitted first), the warm start of a body at rest; how far it was balanced.
StartBalance BalanceGuess(Guess guess, bool moving, const IslandProblem& problem,
                          const IslandLayout& layout, const IslandScales& scales,
                          Eigen::VectorXd& z);

}  // namespace ecpsim::engine::hull
