#include "engine/models/hull_model.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "engine/models/balanced_start.h"
#include "engine/solver/complementarity_solver.h"
#include "engine/mncp/contact_window.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/mncp/mncp_system.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "engine/solution_trend.h"
#include "geometry/convex_separation.h"
#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

// a guess's slip multiplier starts slightly positive: (σ, ζ) = (0, 0) is the kink of φ_FB
constexpr double kInitialSigmaFraction = 1e-3;  // of the velocity scale
// the window check tolerance relative to the body size: far below any face, far above round-off
constexpr double kWindowCheckRelTol = 1e-9;
// rad: the largest rotation h|ω⁺| of one step; beyond π the end pose Exp(hω⁺) R is reached by a
// smaller rotation too, so the step's solution is not unique (an alias)
constexpr double kMaxStepRotation = M_PI;
// a converged step may gain at most this fraction of the body's energy scale m V² + |p_ext| L / h
// (kinetic, and the potential over its own length) beyond the applied loads' work: the implicit
// step dissipates O(h²) where it is resolved, and the spurious roots the drop sweep found at
// coarse dimensionless steps (a 3 cm plate whose |ω| jumped from 3.7 to 193 rad/s in one step)
// gained 1.6e-2 to 0.94 of it
constexpr double kMaxEnergyGainRel = 1e-3;
// the solver's Jacobian smoothing per unit of ‖Φ‖ (McpOptions): measured on the drop sweep's
// failures, 0.1 solved 4 of the 6 steps left without it (0.01 and 1 fewer). (Left out for the
// first pass's warm start, it sped up good starts, but failed a step: engine/README.md, "The
// first pass's warm start")
constexpr double kJacobianSmoothing = 0.1;
// a solve whose residual has not halved in this many iterations gives up for the next guess:
// Newton halves it every iteration near a solution, and the slowest recoveries seen (the adaptive
// Levenberg–Marquardt steps out of an impact's near-singular Newton matrix, the stability map's
// 10 m/s case at h = 2e-4 s) went 30 iterations without halving before they converged
constexpr int kStallIterations = 45;
// the same for a body alone's warm start in the first pass, whose stall the ladder's next guesses
// and the later passes (with kStallIterations) take over: converged warm starts of the shipped
// scenes went up to 25 iterations without halving; the steps cut short here were solved by the
// next guess, to the same trajectory but at the T-bar push's non-isolated first touch. A warm
// start that lands a tilted body on a face stalls for good (engine/README.md, "The first pass's
// warm start")
constexpr int kWarmStartStallIterations = 15;
// the same for the predicted start (engine/README.md, "The predicted start"), which the warm
// start follows when it stalls: the predicted starts that converged took 2–4 iterations, those
// that stalled 6–14, at events the trend could not foresee
constexpr int kPredictedStallIterations = 5;
// a resting body's contact sticks (balanced_start.h) where its slip multiplier σ is at most this
// fraction of the velocity scale: Newton leaves a sticking σ at round-off (0 … 1e-18 m/s on the
// T-bar at rest, whose velocity scale is 0.1 m/s), far below this
constexpr double kStickingSlipFraction = 1e-12;
// the predicted start is tried only along a trend whose second difference of the body's velocity
// (|Δ²v| + |Δ²ω| L) is below this fraction of its first: where an event (a landing, the
// support moving to another edge) lies within the trend's steps its second difference is as
// large as its first (measured on the T-bar: 1.2–1.6 at its landings and tip-overs, whose
// predicted starts stalled; 0.01–0.12 along its smooth rocking)
constexpr double kMaxTrendBend = 0.5;
// ... or below this fraction of the velocity scale, however it compares with the first: the
// dumbbell rolling almost uniformly bends its trend by more than its first difference, and its
// predicted starts converge (gated by the ratio alone it took 2.9 iterations a step instead of 2.4)
constexpr double kNegligibleBend = 1e-3;
// a hull point that the body's last velocities take deeper than its last ECP by this fraction of
// its length marks a landing on another feature (IslandStepper::Lands), where the sliding guess
// goes first: the warm start of a tilted body falling flat stalled there (the T-bar at 0.35 s
// and 1.35 s, points 6.8 % and 2.6 % of its length deeper; 17 and 22 iterations before the
// sliding guess converged in 7–8), and over scenes/tbar.yaml, dumbbell.yaml and
// tilted_box.yaml the hull model's Newton iterations were fewest from 0.01 to 0.02 (1215 → 1117,
// 569 → 543, 95 → 79 at 0.02; 0.005 and 0.05 gave back part of it)
constexpr double kLandingDip = 0.02;
// the last resort (HullModel::AdvanceAsLastResort: minimum-norm steps, plain Newton) gets this
// many times the solver's iteration budget per guess: on a set of solutions that ends at a degenerate pair (a
// contact touching with zero force, as the table's under the T-bar at a finger's first touch)
// Newton converges linearly, and the T-bar push's first touch at h = 1e-5 … 4e-5 s needed
// up to 3 × the default 60 iterations in one solve (2 × failed one of them); only steps whose
// other passes all failed pay for it
constexpr int kPlainNewtonBudgetFactor = 4;
// a hull face whose multiplier exceeds this fraction of the contact's largest one counts as
// active when looking for a degenerate vertex (SolveAtDegenerateVertex): far above round-off,
// far below the multipliers of faces that carry the contact (measured down to 1.9e-6 of it on
// an anchor mesh's five-face vertex)
constexpr double kDegenerateActiveFraction = 1e-9;
// a hull face whose multiplier is below this fraction of the contact's largest carries no
// measurable part of the contact: at a stalled iterate such faces are weakly active (f_i ≈ 0 and
// l_i ≈ 0 together, the degenerate pairs of the Fischer–Burmeister function), measured at
// 1e-9…1e-12 of the largest around a 52 m handle's rolling edge whose carrying faces had 0.43
// and 0.57 (SolveOnCarryingFaces)
constexpr double kCarryingFraction = 1e-6;

// faces left out at most when a degenerate vertex is resolved: enough for six faces at a vertex
// (a fan of triangles, a quad mesh's pole) to come down to three. A vertex with more active
// faces than three plus the drops left is tried one face at a time without going deeper: the
// tree of drops grows as n³ (a 37 m elk mesh's fan took 680,000 iterations in one step)
constexpr int kMaxDegenerateDrops = 3;
// starts spread along a stalled contact's edge (SolveAlongCarryingEdge): the retinal mesh's
// root was reached from 7 of 17 starts along its 4.7 m edge; 16 keep its spacing within a
// sixteenth of the hull's extent along the edge
constexpr int kEdgeStarts = 16;
// a start-of-step overlap of two hulls along their last normal below this fraction of F's size
// is round-off of a resting contact, and its ejection energy negligible: the overlap itself
// stands for the depth, without a GJK query per step
constexpr double kNegligibleDepthRel = 1e-9;
// an island of several bodies is re-solved on fewer faces only when it stalled within this
// factor of the tolerance: Newton stalls 10–100 × above it between the planes of a degenerate
// vertex (engine/README.md, "Degenerate vertices"), 10⁴ leaves margin
constexpr double kMaxDegenerateStall = 1e4;
// a body alone is re-solved at once within this factor of the tolerance (farther, only its
// warm start's stall, after the first pass's other guesses): its stalls on an edge were measured
// up to 2e5 × above it (the knot mesh's 19 m crease at 2e-7, engine/README.md, "Stalls on an
// edge"); a warm start that stalls where the body lands on a face after a tilt (the T-bar, the
// dumbbell: 4e-3 … 2e-2, 10⁹ × and more) is no solution's neighbour, and the re-solves cost
// 100 … 260 iterations there before the ladder's next guess converged in 8 … 23
constexpr double kMaxOneBodyStall = 1e7;
// growing the window this many times (each by the faces around the constraints the solution
// violated) before the guess counts as failed: a step never falls back to every hull face, whose
// dense Newton matrix costs in proportion to the hull (11,000 unknowns for a fine UV sphere); one
// growth is what a solution that moved past the window's rim needs, the rest is margin
constexpr int kMaxWindowGrowth = 6;

// an island of several bodies whose MNCP has at least this many unknowns is solved with a
// sparse Jacobian (complementarity_solver.h), smaller ones and every one-body island dense (as
// before islands, to the bit): on scenes/dominoes.yaml's first 0.6 s the CPU time was 4.0 s
// all dense, 1.0 s from 150 unknowns, 0.7 s from 200, 1.2 s from 300, 3.4 s from 400
// (engine/README.md, "The island's linear algebra")
constexpr int kMinSparseUnknowns = 200;

// an island's last pass with minimum-norm Newton steps (McpOptions::minimum_norm_steps) factors
// its Newton matrix dense, O(n³) per iteration: up to this size an iteration costs tens of ms
// (nine dominoes, 417 unknowns: their failing step reports after 15 s of guesses and sub-steps
// instead of 2 s), beyond it the pass is left out
constexpr int kMaxMinimumNormUnknowns = 600;

using Other = IslandContact::Other;

// the world point of `shape` at pose (c, R) farthest along the world `direction`
Vector3d WorldSupport(const geometry::ConvexShape& shape, const Vector3d& c, const Matrix3d& R,
                      const Vector3d& direction) {
  return c + R * shape.Support(R.transpose() * direction);
}

class IslandStepper {
 public:
  IslandStepper(const Scene& scene, const Island& island) : scene_(scene), island_(island) {}

  // one step of length h from `state`; not solved if every guess failed. As the last resort
  // (HullModel::AdvanceAsLastResort), the ladder's guesses with minimum-norm steps on the plain
  // Newton iteration instead of its three passes
  AdvanceResult Advance(double t, double h, IslandState& state, bool last_resort) const {
    AdvanceResult result;
    IslandProblem problem = MakeProblem(t, h, state);
    // (the scales and overlaps in the thread's storage, kept from step to step: no step of the
    // hull model runs inside another)
    struct Scratch {
      IslandScales scales;
      std::vector<double> overlaps;
    };
    thread_local Scratch scratch;
    IslandScales& scales = scratch.scales;
    scales.bodies.clear();
    for (size_t i = 0; i < island_.bodies.size(); ++i) {
      const BodyProblem& body = problem.bodies[i];
      scales.bodies.push_back(
          BodyScales(scene_.bodies[island_.bodies[i]], state.bodies[i], body.p_ext, h));
      if (!FreeFlightIsFinite(body, result.tried)) {
        result.residual = INFINITY;
        return result;
      }
    }

    RaiseToGripperDrive(problem, scales);
    RaiseToIslandVelocity(problem, scales);
    SeparatePairs(problem, scales, state, scratch.overlaps);
    const std::vector<double>& overlaps = scratch.overlaps;
    // every contact of an island with bodies touching bodies: a box squeezed between a jaw and
    // a pusher on the ground is indeterminate in how much the ground's sticking friction carries
    // too. A body alone against obstacles keeps the paper's exact law
    if (Coupled(problem)) {
      for (IslandContact& cp : problem.contacts)
        cp.stick_creep = kStickCreepFraction * scales.bodies[cp.body].velocity;
    }

    // windows around the support features at the predicted poses: F's in the direction of −n,
    // a moving G's in +n
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      IslandContact& cp = problem.contacts[k];
      const Vector3d& n = state.contacts[k].n;
      // a contact that ended the last step flat on one face takes one ring fewer: the faces at
      // the support vertex hold that face, and the window check grows the window where the ECP
      // reaches another (engine/README.md, "Large hulls: the window")
      const bool flat = problem.bodies.size() == 1 && cp.other_kind == Other::kFixed &&
                        FlatOnOneFace(state.contacts[k]);
      // ... and a fixed obstacle's contact without a warm start (its first step: a body placed
      // on the ground, or touching it for the first time) one ring more: nothing tells yet where
      // on its hull the ECP will go, and a solve that converges in too small a window is solved
      // again once it has grown (the T-bar's first step, tipping from flat: 25 + 13 Newton
      // iterations, 13 with the ring more; every shipped scene's trajectory bit-identical)
      const bool first = cp.other_kind == Other::kFixed &&
                         !std::holds_alternative<HullWarmStart>(state.contacts[k].warm_start);
      const int rings =
          std::max(scene_.solver.window_rings - (flat ? 1 : 0), 0) + (first ? 1 : 0);
      cp.window = SelectWindow(*cp.hull, PredictedRotation(problem, cp.body).transpose() * -n,
                               rings, scene_.solver.use_window);
      if (cp.other_kind != Other::kFixed) {
        cp.other_window =
            SelectWindow(*cp.other_shape, PredictedOtherRotation(problem, cp).transpose() * n,
                         scene_.solver.window_rings, scene_.solver.use_window);
      }
    }

    // free flight: if every hull ends the step strictly apart from its G when no contact acts,
    // then p = 0 with ν⁺ = ν + M⁻¹ p_ext *is* the MNCP's solution (p_n = 0 ⊥ s > 0; a1, a2 the
    // closest points), so it is taken in closed form — the reduced system of trap 2, exact, and
    // free of the degenerate σ and of round-off in far-apart coordinates
    // (the problem's layout: rebuilt only where a window grows)
    IslandLayout layout = MakeIslandLayout(problem);
    if (MayFlyFree(problem, state)) {
      const VectorXd z = MakeGuess(Guess::kSeparated, problem, layout, state, scales);
      if (AllContactsApart(problem, layout, z, state)) {
        Commit(problem, layout, z, state);
        result.model = StepModel::kFree;
        result.solved = true;
        return result;
      }
    }

    // a body that starts the step inside an obstacle (allowed at t = 0, or round-off) is pushed
    // out within the step: the contact may give it the energy of that ejection
    const double ejection_energy = EjectionEnergy(problem, state, scales, overlaps);

    // in contact (or about to be): the warm start, then the guesses that fit the bodies' motion
    const bool have_warm_start =
        state.contacts.empty() ||
        std::holds_alternative<HullWarmStart>(state.contacts[0].warm_start);
    bool moving = false;
    for (size_t i = 0; i < state.bodies.size(); ++i)
      moving |= IsMoving(state.bodies[i], scales.bodies[i]);
    const bool was_in_contact =
        std::any_of(state.contacts.begin(), state.contacts.end(),
                    [](const ContactState& c) { return c.p_n > 0; });
    GuessLadder ladder = RestartLadder(have_warm_start, was_in_contact, moving);
    // a body landing on another feature of its hull: the sliding guess first (engine/README.md,
    // "Landings")
    if (moving && ladder.front() == Guess::kWarm && Lands(problem, state, scales)) {
      ladder.erase(std::find(ladder.begin(), ladder.end(), Guess::kSliding));
      ladder.insert(ladder.begin(), Guess::kSliding);
    }
    // a body alone, moving in contact along a trend of steps of this length: the warm start
    // extrapolated along it first (engine/README.md, "The predicted start")
    if (ladder.front() == Guess::kWarm && moving && Predictable(problem, state, scales))
      ladder.insert(ladder.begin(), Guess::kPredicted);

    const size_t num_bodies = problem.bodies.size();
    McpOptions options;
    options.tolerance = scene_.solver.tolerance;
    options.jacobian_smoothing = kJacobianSmoothing;

    // the ladder as it is first; only when every guess fails, again with iterates kept in the
    // orthant of the complementarity unknowns (engine/README.md, "Impacts": the merit function
    // has stationary points with σ < 0 — friction pushing along the slip — that capture Newton
    // at hard impacts); and only when that fails too, with minimum-norm Newton steps, for
    // solutions that are not isolated (engine/README.md, "Non-isolated solutions"). The last
    // resort takes minimum-norm steps on the plain iteration with a larger budget: where such a
    // set ends at a degenerate pair Newton converges only linearly, which the stall test takes
    // for a stall, and the Levenberg–Marquardt comparison steps along the set
    struct Pass {
      bool project, minimum_norm, plain_newton;
      const char* name;
    };
    static constexpr Pass kPasses[] = {{false, false, false, ""},
                                       {true, false, false, " (projected)"},
                                       {false, true, false, " (minimum-norm)"},
                                       {false, true, true, " (minimum-norm, plain Newton)"}};
    // the ladder's passes, or the last resort's
    constexpr int kLastResortPass = 3, kPassCount = static_cast<int>(std::size(kPasses));
    const int first_pass = last_resort ? kLastResortPass : 0;
    const int end_pass = last_resort ? kPassCount : kLastResortPass;
    for (int p = first_pass; p < end_pass; ++p) {
      const Pass& pass = kPasses[p];
      // (the layout's size only on the failure path: most steps end in the first pass)
      if (pass.minimum_norm && layout.size > kMaxMinimumNormUnknowns) continue;
      options.project_nonnegative = pass.project;
      options.minimum_norm_steps = pass.minimum_norm;
      options.levenberg_marquardt_rescue = !pass.plain_newton;
      options.max_iterations =
          scene_.solver.max_iterations * (pass.plain_newton ? kPlainNewtonBudgetFactor : 1);
      // a body alone whose warm start stalled far from a solution in the first pass is
      // re-solved from that stall only once every other guess has failed too: where it lands on
      // a face after a tilt the next guess converges, at a finger's first touch only a start
      // along an edge from the warm start's stall did (engine/README.md, "Which stalls are
      // re-solved")
      std::optional<std::pair<IslandProblem, VectorXd>> far_stall;
      for (Guess guess : ladder) {
        // a body alone's warm start in the first pass gives up sooner (engine/README.md, "The
        // first pass's warm start"); the other guesses and passes as before
        const bool first_warm = p == 0 && guess == Guess::kWarm;
        options.stall_iterations = pass.plain_newton                 ? 0
                                   : guess == Guess::kPredicted        ? kPredictedStallIterations
                                   : first_warm && num_bodies == 1     ? kWarmStartStallIterations
                                                                       : kStallIterations;
        const auto note = [&](const std::string& what) {
          result.tried += fmt::format("{}{}{} (h = {:g} s): {}", result.tried.empty() ? "" : "; ",
                                      GuessName(guess), pass.name, h, what);
          ++result.retries;
        };
        for (int growth = 0; growth <= kMaxWindowGrowth; ++growth) {
          VectorXd z = MakeGuess(guess, problem, layout, state, scales);
          // a balanced start often meets the tolerance already: one Newton step takes it to
          // round-off, where a polished one usually is (engine/README.md, "Balanced starts")
          const StartBalance balance = BalanceGuess(guess, moving, problem, layout, scales, z);
          options.start_tolerance = BalancedStartTolerance(balance, options.tolerance);
          // bodies at rest under unchanged loads: the last step's solution usually solves this
          // one too (a stack, a box on the table), and a polished start its step: each is
          // verified on the residual alone
          options.verify_start_first =
              (guess == Guess::kWarm && !moving) || balance == StartBalance::kPolished;
          Attempt attempt = Solve(problem, layout, z, options, scales, ejection_energy, result);
          result.residual = attempt.residual;
          if (attempt.outcome == Outcome::kUnconverged) {
            if (IsNearSolutionStall(layout, attempt)) {
              if (ReSolveStall(problem, layout, z, options, scales, ejection_energy, state,
                               result)) {
                result.solved = true;
                return result;
              }
            } else if (layout.num_bodies == 1 && p == 0 && guess == Guess::kWarm) {
              far_stall.emplace(problem, z);
            }
          }
          if (attempt.outcome != Outcome::kSolved) {
            note(attempt.Describe());
            break;
          }
          // a converged windowed solution must also solve the full-hull problem: else the
          // window grows around the constraints it violates, and the step is solved again
          if (GrowViolatedWindows(problem, layout, z, scales)) {
            layout = MakeIslandLayout(problem);
            if (growth < kMaxWindowGrowth) continue;
            note(fmt::format("the hull window still left out violated faces after {} growths",
                             kMaxWindowGrowth));
            break;
          }
          Commit(problem, layout, z, state);
          result.solved = true;
          return result;
        }
      }
      if (far_stall && ReSolveStall(far_stall->first, MakeIslandLayout(far_stall->first),
                                    far_stall->second, options, scales, ejection_energy, state,
                                    result)) {
        result.solved = true;
        return result;
      }
    }
    return result;
  }

 private:
  enum class Outcome { kSolved, kUnconverged, kAliased, kGainsEnergy };

  // one solve of the MNCP of `problem` (laid out as `layout`) from `z`, and whether its root is
  // acceptable
  struct Attempt {
    Outcome outcome = Outcome::kUnconverged;
    double residual = INFINITY;
    int iterations = 0;
    std::string Describe() const {
      const char* what = outcome == Outcome::kAliased       ? "aliased rotation, residual"
                         : outcome == Outcome::kGainsEnergy ? "energy gain, residual"
                                                            : "residual";
      return fmt::format("{} {:.3g} after {} iterations", what, residual, iterations);
    }
  };

  Attempt Solve(const IslandProblem& problem, const IslandLayout& layout, VectorXd& z,
                McpOptions& options, const IslandScales& scales, double ejection_energy,
                AdvanceResult& result) const {
    // what the callbacks need, captured by one reference: std::function keeps a lambda that
    // small in place instead of allocating it on every solve
    struct Context {
      const IslandProblem& problem;
      const IslandLayout& layout;
      const VectorXd& row_scale;
      const VectorXd& var_scale;
      const IslandResidualUnits& units;
    };
    // (the scales' storage the thread's, kept from solve to solve: no solve runs inside another)
    struct Scaling {
      VectorXd row_scale, var_scale;
      IslandResidualUnits units;
    };
    thread_local Scaling scaling;
    IslandRowScales(problem, layout, scales, scaling.row_scale);
    IslandVariableScales(problem, layout, scales, scaling.var_scale);
    MakeIslandResidualUnits(problem, scales, options.tolerance, scaling.units);
    const Context c{problem, layout, scaling.row_scale, scaling.var_scale, scaling.units};
    options.measure = [&c](const VectorXd& zz, const VectorXd& F) {
      return IslandMncpResidual(c.problem, c.layout, zz, F, c.row_scale, c.var_scale, c.units);
    };
    McpResult solve;
    if (layout.num_bodies > 1 && layout.size >= kMinSparseUnknowns) {
      const SparseMcpFunction f = [&c](const VectorXd& zz, VectorXd* F, SparseMatrix* J) {
        EvaluateIslandMncpSparse(c.problem, c.layout, zz, F, J);
      };
      solve = SolveMcp(f, layout.num_free, c.row_scale, c.var_scale, z, options);
    } else {
      // SolveMcp hands J over zero (complementarity_solver.h)
      const McpFunction f = [&c](const VectorXd& zz, VectorXd* F, Eigen::MatrixXd* J) {
        EvaluateIslandMncp(c.problem, c.layout, zz, F, J, /*jacobian_is_zero=*/true);
      };
      solve = SolveMcp(f, layout.num_free, c.row_scale, c.var_scale, z, options);
    }
    options.measure = nullptr;
    result.iterations += solve.iterations;
    Attempt attempt;
    attempt.residual = solve.residual;
    attempt.iterations = solve.iterations;
    if (!solve.converged || !z.allFinite()) return attempt;
    // a turn of more than π in one step is an alias: Exp(hω⁺) has the same end pose for a
    // smaller ω⁺, so such a root of the MNCP is a spurious one (it can gain energy); so is one
    // that gains energy the applied loads did not give (engine/README.md, "Roots that gain
    // energy"): the contact can only take energy away
    bool aliased = false;
    for (int b = 0; b < layout.num_bodies; ++b)
      aliased |= problem.h * z.segment<3>(IslandLayout::Velocity(b) + 3).norm() > kMaxStepRotation;
    if (aliased) {
      attempt.outcome = Outcome::kAliased;
    } else if (IslandStepEnergyGain(problem, layout, z) >
               kMaxEnergyGainRel * IslandEnergyScale(problem, scales) + ejection_energy) {
      attempt.outcome = Outcome::kGainsEnergy;
    } else {
      attempt.outcome = Outcome::kSolved;
    }
    return attempt;
  }

  // The re-solves of an attempt that stalled at `z`: Newton stalls just above the tolerance
  // where faces are weakly active at the solution, where four or more hull faces meet at the ECP
  // (a quad mesh's vertex), or on the fold of an edge's moment balance: the faces that carry
  // the contact alone, one face left out, or starts along the edge solve it
  bool ReSolveStall(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                    McpOptions& options, const IslandScales& scales, double ejection_energy,
                    IslandState& state, AdvanceResult& result) const {
    return SolveOnCarryingFaces(problem, layout, z, options, scales, ejection_energy, state,
                                result) ||
           SolveAtDegenerateVertex(problem, layout, z, options, scales, ejection_energy, state,
                                   result) ||
           SolveAlongCarryingEdge(problem, layout, z, options, scales, ejection_energy, state,
                                  result);
  }

  // Whether a stalled attempt may be a degenerate vertex's, weakly active faces' or an edge's
  // stall, for the re-solves on fewer faces and along the edge: when it stalled within
  // kMaxOneBodyStall of the tolerance in an island of one body, within kMaxDegenerateStall in
  // one of several. Far above it the iterate is no solution's neighbour, its multipliers are
  // arbitrary, and the re-solves (each a whole island solve) only multiply the cost: a stack
  // under 10²⁰ m/s² gravity stalled at residual 1.5 and ran twenty re-solves per guess and step.
  bool IsNearSolutionStall(const IslandLayout& layout, const Attempt& attempt) const {
    const double factor = layout.num_bodies == 1 ? kMaxOneBodyStall : kMaxDegenerateStall;
    return attempt.residual <= factor * scene_.solver.tolerance;
  }

  // Where four or more hull faces meet at the ECP, their multipliers are not unique and their
  // planes (merged from near-coplanar triangles) meet only up to the merge tolerance: the true
  // support is one of the tiny vertices where three of them meet, and Newton stalls just above
  // the tolerance between them. Re-solves from the stalled `z` with each of those faces left
  // out of F's window in turn (the smallest multipliers first; where five or more meet, the
  // reduced problem may stall again at four and leaves out one more, up to `depth` in all); a
  // solution whose window check passes — the faces left out hold, as every face outside the
  // window must — is exact. In an island of several bodies only the contact whose rows stall
  // (the largest scaled residual) is tried: the tree of every contact's drops grows as the
  // contacts' count to the power `depth` (nine dominoes: 23 contacts, thousands of island solves
  // in one step).
  bool SolveAtDegenerateVertex(const IslandProblem& problem, const IslandLayout& layout,
                               const VectorXd& z, McpOptions& options, const IslandScales& scales,
                               double ejection_energy, IslandState& state, AdvanceResult& result,
                               int depth = kMaxDegenerateDrops) const {
    if (depth == 0 || !z.allFinite()) return false;
    const int stalled = layout.num_bodies > 1 ? StalledContact(problem, layout, z, scales) : -1;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      if (stalled >= 0 && static_cast<int>(k) != stalled) continue;
      const MncpLayout::Contact& L = layout.contacts[k];
      const double largest = z.segment(L.l, L.l_count).maxCoeff();
      std::vector<int> active;  // indices into the window, by increasing multiplier
      for (int i = 0; i < L.l_count; ++i)
        if (z[L.l + i] > kDegenerateActiveFraction * largest) active.push_back(i);
      if (active.size() < 4) continue;
      std::sort(active.begin(), active.end(), [&](int a, int b) { return z[L.l + a] < z[L.l + b]; });
      for (size_t drop = 0; drop + 3 < active.size(); ++drop) {
        IslandProblem reduced = problem;
        std::vector<int>& window = reduced.contacts[k].window;
        window.erase(window.begin() + active[drop]);
        const IslandLayout reduced_layout = MakeIslandLayout(reduced);
        VectorXd rz = RemapWindows(problem, layout, z, reduced, reduced_layout);
        const Attempt attempt =
            Solve(reduced, reduced_layout, rz, options, scales, ejection_energy, result);
        const bool can_reach_three = active.size() <= static_cast<size_t>(3 + depth);
        if (attempt.outcome == Outcome::kUnconverged && can_reach_three &&
            SolveAtDegenerateVertex(reduced, reduced_layout, rz, options, scales, ejection_energy,
                                    state, result, depth - 1)) {
          return true;
        }
        if (AcceptReduced(reduced, reduced_layout, rz, attempt, scales, state, result)) {
          return true;
        }
      }
    }
    return false;
  }

  // Re-solves a stall on an edge of F's hull from starts spread along the edge. A body that
  // slides and spins on an edge, its ECP near the centre of rotation, has a moment balance that
  // is not monotone in the ECP's place along the edge (the friction's direction turns there), and
  // Newton can end on the fold between — a local minimum of the merit function with a singular
  // Jacobian, the root elsewhere on the same edge (the drop sweep's knot and retinal meshes: a
  // 19 m crease, a 4.7 m edge). Starts: the stalled iterate and each carrying face's own solution,
  // each with the ECPs moved along the edge to kEdgeStarts places over the hull's extent along
  // it, nearest first; a root is accepted only as every solve is (converged, no energy gained,
  // the window check). As in SolveAtDegenerateVertex, every contact of a body alone is tried,
  // and in an island of several bodies the stalled one.
  bool SolveAlongCarryingEdge(const IslandProblem& problem, const IslandLayout& layout,
                              const VectorXd& z, McpOptions& options, const IslandScales& scales,
                              double ejection_energy, IslandState& state,
                              AdvanceResult& result) const {
    if (!z.allFinite()) return false;
    const int stalled = layout.num_bodies > 1 ? StalledContact(problem, layout, z, scales) : -1;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      if (stalled >= 0 && static_cast<int>(k) != stalled) continue;
      if (SolveAlongEdgeOf(static_cast<int>(k), problem, layout, z, options, scales,
                           ejection_energy, state, result)) {
        return true;
      }
    }
    return false;
  }

  // SolveAlongCarryingEdge on contact `stalled` alone
  bool SolveAlongEdgeOf(int stalled, const IslandProblem& problem, const IslandLayout& layout,
                        const VectorXd& z, McpOptions& options, const IslandScales& scales,
                        double ejection_energy, IslandState& state, AdvanceResult& result) const {
    const IslandContact& cp = problem.contacts[stalled];
    const MncpLayout::Contact& L = layout.contacts[stalled];
    const std::vector<int> carrying = Carrying(z, L.l, L.l_count);  // window positions
    if (carrying.size() != 2) return false;
    // the edge's direction in F's end-of-step frame, and the hull's extent along it
    const int col = IslandLayout::Velocity(cp.body);
    const EndPose end = PoseAfterStep(problem.bodies[cp.body], z.segment<3>(col),
                                      z.segment<3>(col + 3));
    const Vector3d y = end.R.transpose() * (z.segment<3>(L.a1) - end.c);
    const Vector3d edge_body = cp.hull->Gradient(cp.window[carrying[0]], y)
                                   .cross(cp.hull->Gradient(cp.window[carrying[1]], y));
    if (!(edge_body.norm() > 0)) return false;
    const Vector3d e = edge_body.normalized();
    const double from = (cp.hull->Support(-e) - y).dot(e), to = (cp.hull->Support(e) - y).dot(e);
    std::vector<double> shifts;
    for (int i = 0; i < kEdgeStarts; ++i) shifts.push_back(from + (to - from) * (i + 0.5) / kEdgeStarts);
    std::sort(shifts.begin(), shifts.end(),
              [](double a, double b) { return std::abs(a) < std::abs(b); });
    // the starts' bases: the stalled iterate and each carrying face's own root
    std::vector<VectorXd> bases = {z};
    for (int face : carrying) {
      IslandProblem single = problem;
      single.contacts[stalled].window = {cp.window[face]};
      const IslandLayout single_layout = MakeIslandLayout(single);
      VectorXd sz = RemapWindows(problem, layout, z, single, single_layout);
      if (Solve(single, single_layout, sz, options, scales, ejection_energy, result).outcome ==
          Outcome::kSolved) {
        bases.push_back(RemapWindows(single, single_layout, sz, problem, layout));
      }
    }
    const Vector3d e_world = end.R * e;
    for (double shift : shifts) {
      for (const VectorXd& base : bases) {
        VectorXd start = base;
        start.segment<3>(L.a1) += shift * e_world;
        if (!L.on_plane()) start.segment<3>(L.a2) += shift * e_world;
        const Attempt attempt = Solve(problem, layout, start, options, scales, ejection_energy, result);
        if (AcceptReduced(problem, layout, start, attempt, scales, state, result)) return true;
      }
    }
    return false;
  }

  // the contact whose rows (measured as in the convergence measure, without the round-off
  // floor) hold the largest residual at z
  static int StalledContact(const IslandProblem& problem, const IslandLayout& layout,
                            const VectorXd& z, const IslandScales& scales) {
    VectorXd F;
    EvaluateIslandMncp(problem, layout, z, &F, nullptr);
    const VectorXd row_scale = IslandRowScales(problem, layout, scales);
    const VectorXd var_scale = IslandVariableScales(problem, layout, scales);
    int worst = 0;
    double worst_residual = -1;
    for (size_t k = 0; k < layout.contacts.size(); ++k) {
      ScaledRowResidual r(layout.num_free, z, F, row_scale, var_scale);
      r.AddContact(layout.contacts[k], 1);
      if (r.value() > worst_residual) {
        worst_residual = r.value();
        worst = static_cast<int>(k);
      }
    }
    return worst;
  }

  // Re-solves from the stalled `z` with each of F's windows, and a moving G's, cut to the
  // constraints that carry the contact (multiplier above kCarryingFraction of the largest): the
  // weakly active ones left out, the reduced problem's pairs are no longer degenerate. Exact when
  // its window check passes.
  bool SolveOnCarryingFaces(const IslandProblem& problem, const IslandLayout& layout,
                            const VectorXd& z, McpOptions& options, const IslandScales& scales,
                            double ejection_energy, IslandState& state,
                            AdvanceResult& result) const {
    if (!z.allFinite()) return false;
    IslandProblem reduced = problem;
    bool cut = false;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      if (!(z.segment(L.l, L.l_count).maxCoeff() > 0)) continue;
      std::vector<int> carrying;  // stays sorted, as windows are
      for (int i : Carrying(z, L.l, L.l_count)) carrying.push_back(problem.contacts[k].window[i]);
      cut |= carrying.size() < problem.contacts[k].window.size();
      reduced.contacts[k].window = std::move(carrying);
      // a moving G's constraints alike: a finger's cap rim weakly active beside its side
      if (problem.contacts[k].other_kind == Other::kFixed) continue;
      if (!(z.segment(L.l_g, L.l_g_count).maxCoeff() > 0)) continue;
      std::vector<int> carrying_g;
      for (int j : Carrying(z, L.l_g, L.l_g_count))
        carrying_g.push_back(problem.contacts[k].other_window[j]);
      cut |= carrying_g.size() < problem.contacts[k].other_window.size();
      reduced.contacts[k].other_window = std::move(carrying_g);
    }
    if (!cut) return false;
    const IslandLayout reduced_layout = MakeIslandLayout(reduced);
    VectorXd rz = RemapWindows(problem, layout, z, reduced, reduced_layout);
    const Attempt attempt =
        Solve(reduced, reduced_layout, rz, options, scales, ejection_energy, result);
    return AcceptReduced(reduced, reduced_layout, rz, attempt, scales, state, result);
  }

  // the positions among z's `count` multipliers from `first` on that carry the contact: above
  // kCarryingFraction of the largest
  static std::vector<int> Carrying(const VectorXd& z, int first, int count) {
    const double largest = z.segment(first, count).maxCoeff();
    std::vector<int> carrying;
    for (int i = 0; i < count; ++i)
      if (z[first + i] > kCarryingFraction * largest) carrying.push_back(i);
    return carrying;
  }

  // commits a solution of a problem whose windows were cut (faces left out) when it converged
  // and every face outside its windows holds (the window check): then it is exact
  bool AcceptReduced(const IslandProblem& reduced, const IslandLayout& layout, const VectorXd& z,
                     const Attempt& attempt, const IslandScales& scales, IslandState& state,
                     AdvanceResult& result) const {
    if (attempt.outcome != Outcome::kSolved) return false;
    IslandProblem checked = reduced;
    if (GrowViolatedWindows(checked, layout, z, scales)) return false;
    Commit(reduced, layout, z, state);
    result.residual = attempt.residual;
    return true;
  }

  // the face index → multiplier of `from_window` carried to `to_window` (0 for a face new to it)
  static void CarryByFace(const std::vector<int>& from_window, const VectorXd& from, int from_at,
                          const std::vector<int>& to_window, VectorXd& to, int to_at) {
    for (size_t i = 0; i < to_window.size(); ++i) {
      const auto it = std::find(from_window.begin(), from_window.end(), to_window[i]);
      if (it != from_window.end()) to[to_at + i] = from[from_at + (it - from_window.begin())];
    }
  }

  // `z` of `from` (laid out as `from_layout`) moved to `to`'s layout: the same unknowns,
  // multipliers matched by face index (0 for a face new to a window)
  static VectorXd RemapWindows(const IslandProblem& from, const IslandLayout& from_layout,
                               const VectorXd& z, const IslandProblem& to,
                               const IslandLayout& to_layout) {
    VectorXd out = VectorXd::Zero(to_layout.size);
    out.head(IslandLayout::Velocity(to_layout.num_bodies)) =
        z.head(IslandLayout::Velocity(from_layout.num_bodies));
    for (size_t k = 0; k < to.contacts.size(); ++k) {
      const MncpLayout::Contact& A = from_layout.contacts[k];
      const MncpLayout::Contact& B = to_layout.contacts[k];
      // the free block (a1 … p_r: 10 unknowns, 6 on a plane) and G's multipliers (none on a plane)
      out.segment(B.a1, B.p_r + 1 - B.a1) = z.segment(A.a1, A.p_r + 1 - A.a1);
      if (B.l_g_count > 0)
        CarryByFace(from.contacts[k].other_window, z, A.l_g, to.contacts[k].other_window, out,
                    B.l_g);
      out[B.p_n] = z[A.p_n];
      out[B.sigma] = z[A.sigma];
      CarryByFace(from.contacts[k].window, z, A.l, to.contacts[k].window, out, B.l);
    }
    return out;
  }

  // A body's own velocity scale (its speed, or g h at rest) is far below what a contact with a
  // moving body brings it: a box at rest hit at 1.5 m/s measured its impulse in units of its
  // weight's impulse per step (10⁴ × smaller), and Newton diverged. In an island of several
  // bodies, or against a kinematic body, each body's velocity scale is at least the largest of
  // the island's (and of the kinematic bodies' speeds over the bodies' lengths); its impulse
  // scale follows (m V). A body alone against obstacles keeps its own.
  // whether bodies touch bodies in the island (several bodies, or one against a kinematic body)
  static bool Coupled(const IslandProblem& problem) {
    return std::any_of(problem.contacts.begin(), problem.contacts.end(),
                       [](const IslandContact& cp) { return cp.other_kind != Other::kFixed; });
  }

  // a jaw moves as its gripper drives it: at the frame's velocity across the axis, turning with
  // it, and closing under the actuator's impulse, none of which its applied loads show
  static void RaiseToGripperDrive(const IslandProblem& problem, IslandScales& scales) {
    for (const IslandGripper& g : problem.grippers) {
      for (int j = 0; j < 2; ++j) {
        Scales& s = scales.bodies[g.jaws[j]];
        const double mass = problem.bodies[g.jaws[j]].mass;
        const double drive = g.v[j].norm() + g.w[j].norm() * s.length + g.grip / mass;
        if (s.velocity >= drive) continue;
        s.velocity = drive;
        s.impulse = mass * drive;
      }
    }
  }

  static void RaiseToIslandVelocity(const IslandProblem& problem, IslandScales& scales) {
    double velocity = 0;
    for (const Scales& s : scales.bodies) velocity = std::max(velocity, s.velocity);
    for (const IslandContact& cp : problem.contacts) {
      if (cp.other_kind != Other::kKinematic) continue;
      const KinematicBody& g = problem.kinematic[cp.other];
      velocity = std::max(velocity, g.v.norm() + g.w.norm() * scales.bodies[cp.body].length);
    }
    if (!Coupled(problem)) return;
    for (size_t b = 0; b < scales.bodies.size(); ++b) {
      Scales& s = scales.bodies[b];
      if (s.velocity >= velocity) continue;
      s.velocity = velocity;
      s.impulse = problem.bodies[b].mass * velocity;
    }
  }

  // the island's problem at the start of the step: its bodies (StartOfStep), the kinematic
  // bodies its contacts touch (pose and prescribed twist over [t, t + h]) and its contacts, G's
  // window all of a fixed obstacle's constraints
  IslandProblem MakeProblem(double t, double h, const IslandState& state) const {
    IslandProblem p;
    p.h = h;
    for (size_t i = 0; i < island_.bodies.size(); ++i)
      p.bodies.push_back(StartOfStep(scene_, island_.bodies[i], state.bodies[i], t, h));
    // scene index → index into p.kinematic, for the few kinematic bodies the island touches
    std::vector<std::pair<int, int>> kinematic_of;
    for (int id : island_.contacts) {
      const ContactPair& pair = scene_.contacts[id];
      IslandContact cp;
      cp.body = IslandIndex(pair.body);
      cp.hull = scene_.bodies[pair.body].hull.get();
      cp.friction = pair.friction;
      if (!pair.WithBody()) {
        cp.other_kind = Other::kFixed;
        cp.other_shape = scene_.obstacles[pair.obstacle].shape.get();
        cp.other_window.resize(cp.other_shape->NumConstraints());
        std::iota(cp.other_window.begin(), cp.other_window.end(), 0);
      } else {
        const Body& other = scene_.bodies[pair.other_body];
        cp.other_shape = other.hull.get();
        if (other.IsKinematic()) {
          auto known = std::find_if(kinematic_of.begin(), kinematic_of.end(),
                                    [&](const auto& k) { return k.first == pair.other_body; });
          if (known == kinematic_of.end()) {
            const KinematicPose pose = other.motion->PoseAt(t);
            const KinematicMotion::Twist twist = other.motion->StepTwist(t, h);
            p.kinematic.push_back({pose.p, pose.q.toRotationMatrix(), twist.v, twist.w});
            kinematic_of.emplace_back(pair.other_body, static_cast<int>(p.kinematic.size()) - 1);
            known = kinematic_of.end() - 1;
          }
          cp.other_kind = Other::kKinematic;
          cp.other = known->second;
        } else {
          cp.other_kind = Other::kBody;
          cp.other = IslandIndex(pair.other_body);
        }
      }
      p.contacts.push_back(std::move(cp));
    }
    // the grippers whose jaws are in the island (both are: FormIslands joins them)
    for (const Gripper& gripper : scene_.grippers) {
      const auto jaw = std::find(island_.bodies.begin(), island_.bodies.end(), gripper.jaws[0]);
      if (jaw == island_.bodies.end()) continue;
      const int jaw0 = static_cast<int>(jaw - island_.bodies.begin());
      const int jaw1 = IslandIndex(gripper.jaws[1]);
      p.grippers.push_back(
          MakeIslandGripper(gripper, p.bodies[jaw0], p.bodies[jaw1], jaw0, jaw1, t, h));
      SetGripperFreeFlight(p.grippers.back(), p.bodies);
    }
    return p;
  }

  int IslandIndex(int scene_body) const {
    const auto it = std::find(island_.bodies.begin(), island_.bodies.end(), scene_body);
    ECPSIM_DEMAND(it != island_.bodies.end());
    return static_cast<int>(it - island_.bodies.begin());
  }

  // the rotation of island body b at the end of the step if it kept its angular velocity
  static Matrix3d PredictedRotation(const IslandProblem& problem, int b) {
    const BodyProblem& body = problem.bodies[b];
    return ExpMap(problem.h * body.w) * body.R;
  }
  static Matrix3d PredictedOtherRotation(const IslandProblem& problem, const IslandContact& cp) {
    if (cp.other_kind == Other::kBody) return PredictedRotation(problem, cp.other);
    const KinematicBody& g = problem.kinematic[cp.other];
    return ExpMap(problem.h * g.w) * g.R;
  }

  // AllContactsApart's answer for the separated guess where a fixed G decides it, without
  // building the guess: false if a fixed contact's hull, at the free-flight end pose, does not end
  // strictly outside its half-space (its support point in −n, the separated guess's a1, computed
  // as MakeGuess does) or its G is no half-space; true where that does not decide it. A body on
  // the ground fails here, at the cost of one support point instead of the whole guess
  static bool MayFlyFree(const IslandProblem& problem, const IslandState& state) {
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const IslandContact& cp = problem.contacts[k];
      if (cp.other_kind != Other::kFixed) continue;
      if (!cp.other_shape->IsHalfSpace()) return false;
      const BodyProblem& body = problem.bodies[cp.body];
      const EndPose pose = PoseAfterStep(body, body.free.v, body.free.w);
      const Vector3d& n = state.contacts[k].n;
      const Vector3d a1 = WorldSupport(*cp.hull, pose.c, pose.R, -n);
      if (!(cp.other_shape->Value(0, a1) > 0)) return false;
    }
    return true;
  }

  // true if every contact's G is apart from the separated guess's a1 (F's support point in −n at
  // the free-flight end pose): a half-space obstacle strictly below a1, a moving G whose support
  // point a2 in +n lies strictly behind a1 along n (the plane normal to n between them separates
  // the hulls); any other obstacle: false
  static bool AllContactsApart(const IslandProblem& problem, const IslandLayout& layout,
                               const VectorXd& z, const IslandState& state) {
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const IslandContact& cp = problem.contacts[k];
      const MncpLayout::Contact& L = layout.contacts[k];
      if (cp.other_kind == Other::kFixed) {
        if (!cp.other_shape->IsHalfSpace()) return false;
        if (!(cp.other_shape->Value(0, z.segment<3>(L.a1)) > 0)) return false;
      } else if (!(state.contacts[k].n.dot(z.segment<3>(L.a1) - z.segment<3>(L.a2)) > 0)) {
        return false;
      }
    }
    return true;
  }

  // A pair's last normal orients its guesses and hull windows and is the axis of its ejection
  // allowance. One that was not solved in the last step — its first, whose normal is the line
  // of the centres, or one coming back into reach — may face a direction along which hulls that
  // are apart overlap; from there Newton found roots where a finger 4 mm behind a box kicked it
  // into touching at the end of the step. Such a pair takes the candidate axis that separates
  // its start-of-step hulls the most (the separating axis where one exists).
  // Per contact, into `overlaps`, the overlap of the two hulls' extents along its normal at the
  // start of the step (m; 0 for a fixed G), after a pair that did not push in the last step got
  // the best separating axis for its normal where the last one leaves them overlapping (a pair
  // that pushed keeps its solved normal: its warm start's friction is in that normal's frame)
  static void SeparatePairs(const IslandProblem& problem, const IslandScales& scales,
                            IslandState& state, std::vector<double>& overlaps) {
    overlaps.assign(problem.contacts.size(), 0.0);
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const IslandContact& cp = problem.contacts[k];
      if (cp.other_kind == Other::kFixed) continue;
      Vector3d& n = state.contacts[k].n;
      const auto [X_F, X_G] = StartPoses(problem, cp);
      overlaps[k] = -geometry::SeparationAlong(*cp.hull, X_F, *cp.other_shape, X_G, n).separation;
      if (state.contacts[k].p_n > 0 ||
          overlaps[k] <= kNegligibleDepthRel * scales.bodies[cp.body].length) {
        continue;
      }
      const geometry::AxisSeparation best =
          geometry::BestSeparatingAxis(*cp.hull, X_F, *cp.other_shape, X_G, {n});
      n = best.axis;
      overlaps[k] = -best.separation;
    }
  }

  // J: twice the kinetic energy of moving the bodies out of their deepest start-of-step
  // penetration of any G within one step, plus the applied impulses' work over that depth;
  // `overlaps` as SeparatePairs returns them
  static double EjectionEnergy(const IslandProblem& problem, const IslandState& state,
                               const IslandScales& scales, const std::vector<double>& overlaps) {
    double depth = 0;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const IslandContact& cp = problem.contacts[k];
      const BodyProblem& body = problem.bodies[cp.body];
      const Vector3d& n = state.contacts[k].n;
      if (cp.other_kind == Other::kFixed) {
        // F's deepest point along the last normal: a lower bound of the depth, exact for a
        // half-space
        const Vector3d lowest = WorldSupport(*cp.hull, body.c, body.R, -n);
        const double g = cp.other_shape->Value(LargestConstraint(*cp.other_shape, lowest), lowest);
        depth = std::max(depth, -g);
        continue;
      }
      // the overlap of the two hulls' extents along the normal bounds the depth from above
      // (SeparatePairs made it the best candidate axis), and is the depth of a resting or pushed
      // pair. Where the candidates leave an overlap, the depth is measured (GJK and EPA): an
      // overlap that is not one (two cylinders side by side, crossed edges) would let the
      // contact give the bodies energy they never had
      double pair_depth = overlaps[k];
      const double length = scales.bodies[cp.body].length;
      if (pair_depth > kNegligibleDepthRel * length) {
        const auto [X_F, X_G] = StartPoses(problem, cp);
        pair_depth = std::min(pair_depth, geometry::PenetrationDepth(*cp.hull, X_F, *cp.other_shape,
                                                                     X_G, length));
      }
      depth = std::max(depth, pair_depth);
    }
    const double speed = depth / problem.h;
    double energy = 0;
    for (const BodyProblem& body : problem.bodies)
      energy += body.mass * speed * speed + body.p_ext.head<3>().norm() * speed;
    return energy;
  }

  // F's and G's poses at the start of the step (a moving G's)
  static std::pair<Eigen::Isometry3d, Eigen::Isometry3d> StartPoses(const IslandProblem& problem,
                                                                      const IslandContact& cp) {
    const auto pose = [](const Vector3d& c, const Matrix3d& R) {
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = R;
      X.translation() = c;
      return X;
    };
    const BodyProblem& body = problem.bodies[cp.body];
    if (cp.other_kind == Other::kBody) {
      const BodyProblem& other = problem.bodies[cp.other];
      return {pose(body.c, body.R), pose(other.c, other.R)};
    }
    const KinematicBody& g = problem.kinematic[cp.other];
    return {pose(body.c, body.R), pose(g.c, g.R)};
  }

  // whether `c` ended its step pressed onto one hull face alone: a normal impulse, and one face
  // multiplier above kDegenerateActiveFraction of the largest
  static bool FlatOnOneFace(const ContactState& c) {
    const auto* warm = std::get_if<HullWarmStart>(&c.warm_start);
    if (warm == nullptr || !(c.p_n > 0) || warm->l.size() == 0) return false;
    const double largest = warm->l.maxCoeff();
    if (!(largest > 0)) return false;
    return (warm->l.array() > kDegenerateActiveFraction * largest).count() == 1;
  }

  // Whether a body alone on one fixed obstacle lands in this step on another part of its hull
  // than the one it touched: at the end pose of its last velocities, a hull point goes deeper
  // along the contact's normal than the last ECP (carried with the body) by kLandingDip of its
  // length. Rocking on an edge or a vertex keeps the ECP the deepest point; a tilted body
  // falling flat turns its face under the ground by its overshoot times the face's width
  static bool Lands(const IslandProblem& problem, const IslandState& state,
                    const IslandScales& scales) {
    if (problem.bodies.size() != 1 || problem.contacts.size() != 1) return false;
    const IslandContact& cp = problem.contacts[0];
    const ContactState& last = state.contacts[0];
    if (cp.other_kind != Other::kFixed || !(last.p_n > 0)) return false;
    const BodyProblem& body = problem.bodies[0];
    const EndPose end = PoseAfterStep(body, state.bodies[0].v_WB, state.bodies[0].w_WB);
    const Vector3d deepest = WorldSupport(*cp.hull, end.c, end.R, -last.n);
    const Vector3d ecp = end.c + end.R * (body.R.transpose() * (last.a1 - body.c));
    return last.n.dot(ecp - deepest) > kLandingDip * scales.bodies[0].length;
  }

  // contact k's point extrapolated along its trend to the end of this step, if it has one for
  // steps of this length
  static std::optional<SolutionTrend::Point> PredictedPoint(const IslandProblem& problem,
                                                            const IslandState& state, int k) {
    const auto* warm = std::get_if<HullWarmStart>(&state.contacts[k].warm_start);
    if (warm == nullptr) return std::nullopt;
    const BodyState& body = state.bodies[problem.contacts[k].body];
    return PredictPoint(warm->trend, TrendPoint(body, state.contacts[k], warm->s), problem.h);
  }

  // whether the predicted start applies: one body against fixed obstacles, every contact with a
  // trend for this step that bends its velocity less than kMaxTrendBend
  static bool Predictable(const IslandProblem& problem, const IslandState& state,
                          const IslandScales& scales) {
    if (problem.bodies.size() != 1 || problem.contacts.empty()) return false;
    const double L = scales.bodies[0].length;
    const auto speed = [L](const SolutionTrend::Point& d) {
      return d.head<3>().norm() + d.segment<3>(3).norm() * L;
    };
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      if (problem.contacts[k].other_kind != Other::kFixed) return false;
      const auto* warm = std::get_if<HullWarmStart>(&state.contacts[k].warm_start);
      if (warm == nullptr || !Predicts(warm->trend, problem.h)) return false;
      const SolutionTrend& trend = warm->trend;
      const double bend = speed(trend.second);
      if (!(bend <= kMaxTrendBend * speed(trend.first) ||
            bend <= kNegligibleBend * scales.bodies[0].velocity))
        return false;
    }
    return true;
  }

  // the predicted start's unknowns of contact k over its warm start's, with its body's velocity
  // (every contact of the body carries the same trend of it); the complementarity unknowns kept
  // ≥ 0, the multipliers l and l_G the warm start's (a face's multiplier follows no trend)
  static void SetPredicted(const IslandProblem& problem, const IslandLayout& layout,
                           const IslandState& state, int k, VectorXd& z) {
    const std::optional<SolutionTrend::Point> point = PredictedPoint(problem, state, k);
    if (!point) return;
    const MncpLayout::Contact& L = layout.contacts[k];
    z.segment<6>(IslandLayout::Velocity(problem.contacts[k].body)) = point->head<6>();
    z.segment<3>(L.a1) = point->segment<3>(6);
    if (!L.on_plane()) {
      z.segment<3>(L.a2) = point->segment<3>(9);
      z[L.s] = std::max((*point)[12], 0.0);
    }
    z[L.p_n] = std::max((*point)[13], 0.0);
    z[L.p_t] = (*point)[14];
    z[L.p_o] = (*point)[15];
    z[L.p_r] = (*point)[16];
    z[L.sigma] = std::max((*point)[17], 0.0);
  }

  VectorXd MakeGuess(Guess guess, IslandProblem& problem, const IslandLayout& layout,
                     const IslandState& state, const IslandScales& scales) const {
    VectorXd z = VectorXd::Zero(layout.size);
    // free-flight velocities as the starting point of a fresh guess; the last ones for warm starts
    const bool from_last = guess == Guess::kWarm || guess == Guess::kPredicted;
    for (int b = 0; b < layout.num_bodies; ++b) {
      const int col = IslandLayout::Velocity(b);
      const auto& [v_free, w_free] = problem.bodies[b].free;
      z.segment<3>(col) = from_last ? state.bodies[b].v_WB : v_free;
      z.segment<3>(col + 3) = from_last ? state.bodies[b].w_WB : w_free;
    }

    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      IslandContact& cp = problem.contacts[k];
      const MncpLayout::Contact& L = layout.contacts[k];
      const ContactState& previous = state.contacts[k];
      const Friction& fr = cp.friction;
      const BodyProblem& body = problem.bodies[cp.body];
      const int col = IslandLayout::Velocity(cp.body);
      cp.tangent_reference = TangentReference(previous.n);
      const double sigma0 = kInitialSigmaFraction * scales.bodies[cp.body].velocity;

      const auto* warm = std::get_if<HullWarmStart>(&previous.warm_start);
      if (from_last && warm != nullptr) {
        z.segment<3>(L.a1) = previous.a1;
        if (!L.on_plane()) {
          z.segment<3>(L.a2) = previous.a2;
          z[L.s] = warm->s;
        }
        z[L.p_t] = previous.p_t;
        z[L.p_o] = previous.p_o;
        z[L.p_r] = previous.p_r;
        z[L.p_n] = previous.p_n;
        z[L.sigma] = previous.sigma;
        if (guess == Guess::kPredicted) SetPredicted(problem, layout, state, static_cast<int>(k), z);
        // (on a plane l_G = 1 is no unknown)
        if (cp.other_kind != Other::kFixed) {
          CarryByFace(warm->other_window, warm->l_g, 0, cp.other_window, z, L.l_g);
        } else if (!L.on_plane()) {
          z.segment(L.l_g, L.l_g_count) = warm->l_g;
        }
        // carry hull multipliers over by face index (the window may have moved); windows are
        // sorted (SelectWindow), so a binary search does it without building a map every step
        const std::vector<int>& window = warm->window;
        for (int i = 0; i < L.l_count; ++i) {
          const auto it = std::lower_bound(window.begin(), window.end(), cp.window[i]);
          if (it != window.end() && *it == cp.window[i]) z[L.l + i] = warm->l[it - window.begin()];
        }
        continue;
      }

      // geometric guess at the free-flight poses: F's support point in the direction −n
      const Vector3d n = previous.n;
      const EndPose pose = PoseAfterStep(body, z.segment<3>(col), z.segment<3>(col + 3));
      const Vector3d support = WorldSupport(*cp.hull, pose.c, pose.R, -n);
      // a contact without a warm start (new to the ladder) starts as separated
      const bool separated = guess == Guess::kSeparated || guess == Guess::kWarm;
      Vector3d a1 = support;
      if (!separated) a1 = pose.c - n * n.dot(pose.c - support);  // under the CM
      Vector3d a2, N;
      Vector3d v_other = Vector3d::Zero();  // G's velocity at the contact, for the sliding guess
      if (cp.other_kind == Other::kFixed) {
        const auto [projection, active_g] = ProjectOntoObstacle(*cp.other_shape, a1);
        a2 = projection;
        if (!L.on_plane()) z[L.l_g + active_g] = 1;
        N = cp.other_shape->Gradient(active_g, a2);
      } else {
        // G's support point in +n at its end pose, and a1 on its support plane when touching
        const EndPose other = OtherEndPose(problem, z, static_cast<int>(k));
        const Vector3d top = WorldSupport(*cp.other_shape, other.c, other.R, n);
        a2 = separated ? top : Vector3d(a1 - n * n.dot(a1 - top));
        const Vector3d y_g = other.R.transpose() * (a2 - other.c);
        // G's window constraint whose world normal is most aligned with n carries its cone
        const int best_g = MostOpposedWindowConstraint(*cp.other_shape, cp.other_window,
                                                       other.R, y_g, -n);
        z[L.l_g + best_g] = 1;
        N = other.R * cp.other_shape->Gradient(cp.other_window[best_g], y_g);
        if (cp.other_kind == Other::kKinematic) {
          const KinematicBody& g = problem.kinematic[cp.other];
          v_other = g.v + g.w.cross(a2 - other.c);
        } else {
          const int other_col = IslandLayout::Velocity(cp.other);
          v_other = z.segment<3>(other_col) + Vector3d(z.segment<3>(other_col + 3)).cross(a2 - other.c);
        }
      }
      z.segment<3>(L.a1) = a1;
      if (!L.on_plane()) {
        z.segment<3>(L.a2) = a2;
        z[L.s] = separated ? std::max(0.0, (a1 - a2).dot(N) / N.squaredNorm()) : 0;
      }
      // the window face whose world normal is most opposed to N carries the cone
      const Vector3d y = pose.R.transpose() * (a1 - pose.c);
      const int best = MostOpposedWindowConstraint(*cp.hull, cp.window, pose.R, y, N);
      z[L.l + best] = 1;
      z[L.sigma] = sigma0;
      if (separated) continue;

      // in contact: the normal impulse that cancels gravity and the approach velocity
      const Vector3d& v_start = state.bodies[cp.body].v_WB;
      double p_n = 0;
      Vector3d v_tangent;
      if (cp.other_kind == Other::kFixed) {
        p_n = std::max(body.mass * (-n.dot(z.segment<3>(col))), 0.0) +
              std::max(-body.mass * scene_.gravity.dot(n) * problem.h, 0.0);
        v_tangent = v_start - n * n.dot(v_start);
      } else {
        // F and G end the step with a common normal velocity: G's own when kinematic, the
        // momentum-weighted mean of the two when G is a body (a perfectly inelastic impact)
        double v_common = n.dot(v_other);
        if (cp.other_kind == Other::kBody) {
          const double m_g = problem.bodies[cp.other].mass;
          const int other_col = IslandLayout::Velocity(cp.other);
          v_common = (body.mass * n.dot(z.segment<3>(col)) +
                      m_g * n.dot(z.segment<3>(other_col))) / (body.mass + m_g);
          const Vector3d v_g = z.segment<3>(other_col);
          z.segment<3>(other_col) = v_g - n * (n.dot(v_g) - v_common);
        }
        p_n = std::max(body.mass * (v_common - n.dot(z.segment<3>(col))), 0.0) +
              std::max(-body.mass * scene_.gravity.dot(n) * problem.h, 0.0);
        const Vector3d v_f = z.segment<3>(col);
        v_tangent = v_f - n * (n.dot(v_f) - v_common);
      }
      z[L.p_n] = p_n;
      z.segment<3>(col) = v_tangent;
      if (guess == Guess::kSliding) {
        const ContactFrame frame = MakeContactFrame(N, cp.tangent_reference);
        const Vector3d slip = v_tangent - v_other;
        const double v_t = frame.t.dot(slip), v_o = frame.o.dot(slip);
        const double v_r = frame.n.dot(state.bodies[cp.body].w_WB);
        SetSlidingFriction(fr, p_n, v_t, v_o, v_r, sigma0, L, z);
      }
    }
    return z;
  }

  // the guess `z` made consistent with the step's equations where balanced_start.h can: the
  // predicted start, the warm start or the sliding guess of a body sliding flat (a predicted
  // start's carrying faces' multipliers fitted where it rocks), the warm start of a body at
  // rest; how far it was balanced
  static StartBalance BalanceGuess(Guess guess, bool moving, const IslandProblem& problem,
                                   const IslandLayout& layout, const IslandScales& scales,
                                   VectorXd& z) {
    if (guess == Guess::kPredicted)
      FitCarryingMultipliers(problem, layout, kDegenerateActiveFraction, z);
    if (moving) {
      if (guess != Guess::kPredicted && guess != Guess::kWarm && guess != Guess::kSliding)
        return StartBalance::kUnbalanced;
      return BalanceSlidingStart(problem, layout, kDegenerateActiveFraction, z);
    }
    return guess == Guess::kWarm && !scales.bodies.empty() &&
                   BalanceRestingStart(problem, layout, kDegenerateActiveFraction,
                                       kStickingSlipFraction * scales.bodies[0].velocity, z)
               ? StartBalance::kBalanced
               : StartBalance::kUnbalanced;
  }

  // grows the windows (F's, and a moving polyhedral G's) of every contact whose windowed
  // solution violates a constraint left out (contact_window.h); false when the solution solves
  // the full-hull problem
  bool GrowViolatedWindows(IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                           const IslandScales& scales) const {
    bool grown = false;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      IslandContact& cp = problem.contacts[k];
      const int col = IslandLayout::Velocity(cp.body);
      const EndPose end = PoseAfterStep(problem.bodies[cp.body], z.segment<3>(col),
                                        z.segment<3>(col + 3));
      const double tolerance = kWindowCheckRelTol * scales.bodies[cp.body].length;
      int active = 0;
      z.segment(L.l, L.l_count).maxCoeff(&active);
      const Vector3d y = end.R.transpose() * (z.segment<3>(L.a1) - end.c);
      const std::vector<int> violated =
          WindowViolations(*cp.hull, cp.window, cp.window[active], y, tolerance);
      if (!violated.empty()) {
        cp.window = GrowWindow(*cp.hull, cp.window, violated);
        grown = true;
      }
      if (cp.other_kind == Other::kFixed) continue;
      const EndPose other = OtherEndPose(problem, z, static_cast<int>(k));
      int active_g = 0;
      z.segment(L.l_g, L.l_g_count).maxCoeff(&active_g);
      const Vector3d y_g = other.R.transpose() * (z.segment<3>(L.a2) - other.c);
      const std::vector<int> violated_g = WindowViolations(
          *cp.other_shape, cp.other_window, cp.other_window[active_g], y_g, tolerance);
      if (!violated_g.empty()) {
        cp.other_window = GrowWindow(*cp.other_shape, cp.other_window, violated_g);
        grown = true;
      }
    }
    return grown;
  }

  void Commit(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
              IslandState& state) const {
    const double h = problem.h;
    // the contacts first: their trends start from the bodies' velocities before the step
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      const IslandContact& cp = problem.contacts[k];
      ContactState& c = state.contacts[k];
      const auto* last = std::get_if<HullWarmStart>(&c.warm_start);
      const SolutionTrend::Point before =
          TrendPoint(state.bodies[cp.body], c, last != nullptr ? last->s : 0.0);
      const ContactGap gap = ContactGapAt(L, cp.other_shape, z);
      c.a1 = z.segment<3>(L.a1);
      c.a2 = gap.a2;
      c.p_t = z[L.p_t];
      c.p_o = z[L.p_o];
      c.p_r = z[L.p_r];
      // complementarity unknowns are ≥ 0 up to the tolerance; report them clamped
      c.p_n = std::max(z[L.p_n], 0.0);
      // without a normal impulse any σ ≥ 0 solves the MNCP (trap 2); report the canonical 0
      c.sigma = c.p_n > 0 ? std::max(z[L.sigma], 0.0) : 0.0;
      const ContactFrame frame =
          MakeContactFrame(IslandContactNormal(problem, layout, z, static_cast<int>(k)),
                           cp.tangent_reference);
      c.n = frame.n;
      c.t = frame.t;
      c.o = frame.o;
      BodyState after;
      after.v_WB = z.segment<3>(IslandLayout::Velocity(cp.body));
      after.w_WB = z.segment<3>(IslandLayout::Velocity(cp.body) + 3);
      const SolutionTrend trend =
          NextTrend(last != nullptr ? &last->trend : nullptr, before, TrendPoint(after, c, gap.s), h);
      // written over the last warm start, whose storage it reuses; on a plane l_G = 1 (its one
      // constraint)
      HullWarmStart& warm = last != nullptr ? *std::get_if<HullWarmStart>(&c.warm_start)
                                            : c.warm_start.emplace<HullWarmStart>();
      warm.s = gap.s;
      if (L.on_plane()) {
        warm.l_g.setOnes(1);
      } else {
        warm.l_g = z.segment(L.l_g, L.l_g_count);
      }
      warm.window = cp.window;
      warm.l = z.segment(L.l, L.l_count);
      if (cp.other_kind != Other::kFixed) {
        warm.other_window = cp.other_window;
      } else {
        warm.other_window.clear();
      }
      warm.trend = trend;
    }
    for (int b = 0; b < layout.num_bodies; ++b) {
      const int col = IslandLayout::Velocity(b);
      const Vector3d v = z.segment<3>(col);
      const Vector3d w = z.segment<3>(col + 3);
      BodyState& body = state.bodies[b];
      body.p_WB += h * v;
      body.Q_WB = IntegrateOrientation(body.Q_WB, w, h);
      body.v_WB = v;
      body.w_WB = w;
    }
  }

  const Scene& scene_;
  const Island& island_;
};

}  // namespace

AdvanceResult HullModel::Advance(const Island& island, double t, double h,
                                 IslandState& state) const {
  return IslandStepper(scene_, island).Advance(t, h, state, /*last_resort=*/false);
}

std::optional<AdvanceResult> HullModel::AdvanceAsLastResort(const Island& island, double t,
                                                            double h, IslandState& state) const {
  return IslandStepper(scene_, island).Advance(t, h, state, /*last_resort=*/true);
}

}  // namespace ecpsim::engine
