#include "engine/models/hull_model.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/models/balanced_start.h"
#include "engine/models/hull_attempt.h"
#include "engine/models/hull_guesses.h"
#include "engine/models/hull_problem.h"
#include "engine/models/hull_selection.h"
#include "engine/models/hull_stall_recovery.h"
#include "engine/models/hull_tuning.h"
#include "engine/models/hull_warm_start.h"
#include "engine/solver/complementarity_solver.h"

namespace ecpsim::engine {
namespace hull {
namespace {

using Eigen::VectorXd;

// The ladder as it is first; only when every guess fails, again with iterates kept in the
// orthant of the complementarity unknowns ("Impacts": stationary points with σ < 0 capture
// Newton at hard impacts); only when that fails too, with minimum-norm Newton steps and no
// Levenberg–Marquardt rescue, for solutions that are not isolated ("Non-isolated solutions"),
// and then with proximal terms in the Newton matrix (sparse, for any size). The last resort
// takes both kinds of steps on the plain iteration with a larger budget: where such a set ends
// at a degenerate pair Newton converges only linearly, which the stall test takes for a stall.
struct Pass {
  bool project, minimum_norm, proximal, plain_newton;
  const char* name;
};
constexpr Pass kPasses[] = {{false, false, false, false, ""},
                            {true, false, false, false, " (projected)"},
                            {false, true, false, false, " (minimum-norm)"},
                            {false, false, true, false, " (proximal)"},
                            {false, true, false, true, " (minimum-norm, plain Newton)"},
                            {false, false, true, true, " (proximal, plain Newton)"}};
constexpr int kLastResortPass = 4;
constexpr int kPassCount = static_cast<int>(std::size(kPasses));

// What a solve's outcome depends on besides its start: the windows (their growths so far) and
// the options a guess sets
struct StartOptions {
  int windows_grown;
  int stall_iterations;
  double start_tolerance;
  bool verify_start_first;
  bool operator==(const StartOptions& o) const {
    return windows_grown == o.windows_grown && stall_iterations == o.stall_iterations &&
           start_tolerance == o.start_tolerance && verify_start_first == o.verify_start_first;
  }
};

// A start a solve failed from: an equal start with equal options fails alike
struct TriedStart {
  VectorXd z;
  StartOptions options;
  bool Repeats(const VectorXd& start, const StartOptions& start_options) const {
    return options == start_options && z.size() == start.size() && z == start;
  }
};

// The pass's failed starts and the current attempt's start, kept in the StepWorkspace: a step
// that ends in its first attempt copies its start into storage of the size it had last step
struct StartsOfPass {
  VectorXd current;
  std::vector<TriedStart> failed;
};

// The passes of one island step over its ladder of guesses. They share the problem, whose
// windows grow where a root leaves out violated faces (and stay grown for later guesses), its
// layout, the bodies' scales and the ejection allowance; the first root that passes every check
// is committed into `state`.
class LadderRun {
 public:
  LadderRun(const Scene& scene, const Island& island, IslandProblem& problem, IslandLayout layout,
            const IslandScales& scales, double ejection_energy, bool moving,
            StepWorkspace& workspace, IslandState& state, AdvanceResult& result)
      : scene_(scene),
        island_(island),
        problem_(problem),
        layout_(std::move(layout)),
        scales_(scales),
        ejection_energy_(ejection_energy),
        moving_(moving),
        workspace_(workspace),
        state_(state),
        result_(result) {
    options_.tolerance = scene.solver.tolerance;
    options_.jacobian_smoothing = kJacobianSmoothing;
    // contacts that couple bodies may share loads indeterminately: the exact problem's root of
    // least patch energy ("Steps whose solutions form a set")
    if (scene.solver.selection == Selection::kLeastEnergy && Coupled(problem)) {
      select_ = [this](const IslandProblem& root_problem, const IslandLayout& root_layout,
                       VectorXd& z) {
        std::optional<VectorXd> last;
        const auto has_warm_start = [](const ContactState& c) {
          return c.warm_start.Get<HullWarmStart>() != nullptr;
        };
        if (std::any_of(state_.contacts.begin(), state_.contacts.end(), has_warm_start)) {
          IslandProblem scratch = root_problem;  // (MakeGuess sets the same tangent references)
          last = MakeGuess(Guess::kWarm, scene_.gravity, scratch, root_layout, state_, scales_);
        }
        SelectLeastEnergyRoot(scene_, island_, root_problem, root_layout, scales_, ejection_energy_,
                              options_.tolerance, workspace_, z, last ? &*last : nullptr);
      };
    }
  }

  // pass `p` over `ladder`; true once a root is committed
  bool RunPass(int p, const GuessLadder& ladder) {
    const Pass& pass = kPasses[p];
    // (the layout's size only on the failure path: most steps end in the first pass)
    if (pass.minimum_norm && layout_.size > kMaxMinimumNormUnknowns) return false;
    options_.project_nonnegative = pass.project;
    options_.minimum_norm_steps = pass.minimum_norm;
    options_.proximal_weight = pass.proximal ? kProximalWeight : 0;
    // minimum-norm steps never move along a set of solutions, and the Levenberg–Marquardt
    // comparison step, whose damping restores nothing there, would ("Non-isolated solutions")
    options_.levenberg_marquardt_rescue = !pass.plain_newton && !pass.minimum_norm;
    options_.max_iterations =
        scene_.solver.max_iterations * (pass.plain_newton ? kPlainNewtonBudgetFactor : 1);
    // a body alone whose warm start stalled far from a root in the first pass is re-solved from
    // that stall only once every other guess has failed too ("Which stalls are re-solved")
    std::optional<std::pair<IslandProblem, VectorXd>> far_stall;
    starts_.failed.clear();
    for (Guess guess : ladder) {
      options_.stall_iterations =
          StallIterations(guess, p == 0, pass.plain_newton, problem_.bodies.size());
      if (TryGuess(guess, p, pass, far_stall)) return true;
    }
    return far_stall &&
           ReSolveStall(far_stall->first, MakeIslandLayout(far_stall->first), far_stall->second,
                        options_, scales_, ejection_energy_, workspace_, state_, result_, select_);
  }

 private:
  // `guess` solved, its windows grown until its root holds for the whole hulls; true once a
  // root is committed. A far stall of a body alone's warm start in the first pass is kept in
  // `far_stall`
  bool TryGuess(Guess guess, int p, const Pass& pass,
                std::optional<std::pair<IslandProblem, VectorXd>>& far_stall) {
    for (int growth = 0; growth <= kMaxWindowGrowth; ++growth) {
      VectorXd z = MakeGuess(guess, scene_.gravity, problem_, layout_, state_, scales_);
      // a balanced start often meets the tolerance already: one Newton step takes it to
      // round-off, where a polished one usually is ("Balanced starts")
      const StartBalance balance = BalanceGuess(guess, moving_, problem_, layout_, scales_, z);
      options_.start_tolerance = BalancedStartTolerance(balance, options_.tolerance);
      // bodies at rest under unchanged loads, or moving on as they did (the warm start's points
      // carried with them, CarriesPoints): the last step's solution usually solves this one
      // too, and a polished start its step: each is verified on the residual alone
      options_.verify_start_first = (guess == Guess::kWarm && (!moving_ || carries_points_)) ||
                                    balance == StartBalance::kPolished;
      // two guesses may make the same start (an island's resting and sliding guesses where no
      // contact has a warm start): its solve would fail again, iteration for iteration
      const StartOptions start_options{windows_grown_, options_.stall_iterations,
                                       options_.start_tolerance, options_.verify_start_first};
      for (const TriedStart& tried : starts_.failed)
        if (tried.Repeats(z, start_options)) return false;
      // (kept in the workspace: the solve leaves z at its last iterate)
      starts_.current = z;
      if (CommitSelectedStart(guess, z)) return true;
      const Attempt attempt = SolveAttempt(problem_, layout_, z, options_, scales_,
                                           ejection_energy_, workspace_, result_);
      result_.residual = attempt.residual;
      if (attempt.outcome != Outcome::kSolved)
        starts_.failed.push_back({starts_.current, start_options});
      if (attempt.outcome == Outcome::kUnconverged) {
        if (IsNearSolutionStall(layout_, attempt, scene_.solver.tolerance)) {
          if (ReSolveStall(problem_, layout_, z, options_, scales_, ejection_energy_, workspace_,
                           state_, result_, select_)) {
            return true;
          }
        } else if (layout_.num_bodies == 1 && p == 0 && guess == Guess::kWarm) {
          far_stall.emplace(problem_, z);
        }
      }
      if (attempt.outcome != Outcome::kSolved) {
        Note(guess, pass, attempt.Describe());
        return false;
      }
      if (select_) select_(problem_, layout_, z);
      // a converged windowed root must also solve the full-hull problem: else the window grows
      // around the constraints it violates, and the step is solved again
      if (GrowViolatedWindows(problem_, layout_, z, scales_)) {
        layout_ = MakeIslandLayout(problem_);
        ++windows_grown_;
        if (growth < kMaxWindowGrowth) continue;
        Note(guess, pass,
             fmt::format("the hull window still left out violated faces after {} growths",
                         kMaxWindowGrowth));
        return false;
      }
      CommitSolution(problem_, layout_, z, state_);
      return true;
    }
    return false;
  }

  // under the selection, where the last step's solution `z` (a selected, exact root) is a root of
  // this step's exact problem that passes every check, the root selected from it as it is,
  // committed where its windows hold for the whole hulls (AcceptReduced); true once committed.
  // It is not first solved with the creep and taken back onto the exact set
  bool CommitSelectedStart(Guess guess, const VectorXd& z) {
    if (!select_ || guess != Guess::kWarm || !options_.verify_start_first) return false;
    IslandProblem exact = problem_;
    for (IslandContact& cp : exact.contacts) cp.stick_creep = 0;
    McpOptions verify = options_;
    verify.max_iterations = 0;
    VectorXd root = z;
    const Attempt attempt =
        SolveAttempt(exact, layout_, root, verify, scales_, ejection_energy_, workspace_, result_);
    return AcceptReduced(problem_, layout_, root, attempt, scales_, state_, result_, select_);
  }

  // a failed guess in the failure's list of what was tried
  void Note(Guess guess, const Pass& pass, const std::string& what) {
    result_.tried.push_back({std::string(GuessName(guess)) + pass.name, problem_.h, what});
    ++result_.retries;
  }

  const Scene& scene_;
  const Island& island_;
  IslandProblem& problem_;
  IslandLayout layout_;  // rebuilt only where a window grows
  const IslandScales& scales_;
  const double ejection_energy_;
  const bool moving_;
  StepWorkspace& workspace_;
  IslandState& state_;
  AdvanceResult& result_;
  // (after problem_, scales_ and state_, which it reads)
  const bool carries_points_ = CarriesPoints(problem_, state_, scales_);
  McpOptions options_;
  RootSelector select_;  // empty: the root as solved
  StartsOfPass& starts_ = workspace_.Part<StartsOfPass>();
  int windows_grown_ = 0;  // the problem's windows' growths so far (each changes its layout)
};

// One step of length h from `state`; not solved if every guess failed. As the last resort, the
// ladder's guesses with minimum-norm steps on the plain Newton iteration instead of its passes.
AdvanceResult AdvanceIsland(const Scene& scene, const Island& island, double t, double h,
                            IslandState& state, Effort effort, StepWorkspace& workspace) {
  AdvanceResult result;
  IslandProblem problem = MakeHullProblem(scene, island, t, h, state);
  // (the scales and overlaps kept in the workspace from step to step)
  struct Scratch {
    IslandScales scales;
    std::vector<double> overlaps;
  };
  Scratch& scratch = workspace.Part<Scratch>();
  IslandScales& scales = scratch.scales;
  if (!MakeIslandScales(scene, island, problem, state, scales, result.tried)) {
    result.residual = INFINITY;
    return result;
  }
  SeparatePairs(problem, scales, state, scratch.overlaps);
  SetStickCreep(scales, problem);
  SelectWindows(scene.solver, state, problem);

  // free flight: if every hull ends the step strictly apart from its G when no contact acts,
  // then p = 0 with ν⁺ = ν + M⁻¹ p_ext *is* the MNCP's solution (p_n = 0 ⊥ s > 0; a1, a2 the
  // closest points), taken in closed form — the reduced system of trap 2, exact, and free of
  // the degenerate σ and of round-off in far-apart coordinates
  IslandLayout layout = MakeIslandLayout(problem);
  if (MayFlyFree(problem, state)) {
    const VectorXd z = MakeGuess(Guess::kSeparated, scene.gravity, problem, layout, state, scales);
    if (AllContactsApart(problem, layout, z, state)) {
      CommitSolution(problem, layout, z, state);
      result.model = StepModel::kFree;
      result.solved = true;
      return result;
    }
  }

  // a body that starts the step inside an obstacle (allowed at t = 0, or round-off) is pushed
  // out within the step: the contact may give it the energy of that ejection
  const double ejection_energy = EjectionEnergy(problem, state, scales, scratch.overlaps);
  // in contact (or about to be): the warm start, then the guesses that fit the bodies' motion
  const bool moving = AnyBodyMoving(state, scales);
  const GuessLadder ladder = HullLadder(problem, state, scales, moving);
  LadderRun run(scene, island, problem, std::move(layout), scales, ejection_energy, moving,
                workspace, state, result);
  const bool last_resort = effort == Effort::kLastResort;
  const int first_pass = last_resort ? kLastResortPass : 0;
  const int end_pass = last_resort ? kPassCount : kLastResortPass;
  for (int p = first_pass; p < end_pass; ++p) {
    if (run.RunPass(p, ladder)) {
      result.solved = true;
      return result;
    }
  }
  return result;
}

}  // namespace
}  // namespace hull

AdvanceResult HullModel::Advance(const Island& island, double t, double h, IslandState& state,
                                 Effort effort) const {
  return hull::AdvanceIsland(scene_, island, t, h, state, effort, workspace_);
}

}  // namespace ecpsim::engine
