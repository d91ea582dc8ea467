#include "engine/step_driver.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <utility>

#include "engine/island_sleep.h"
#include "engine/island_threads.h"
#include "engine/islands.h"
#include "engine/solver/complementarity_solver.h"

namespace ecpsim::engine {
namespace {

// a span that fails is split in two halves, each solved from where the one before ended, down
// to h / 2⁴ (engine/README.md, "Restart ladder": hard impacts and bodies far smaller than g h²
// need the finest)
constexpr int kMaxSplits = 4;

// What an island step's solved spans summed: the contacts' impulses, the largest residual, the
// dearest model and the finest split (as sub-steps of the step)
struct SpanSums {
  std::vector<Eigen::Vector4d> impulse;  // per contact
  double residual = 0;
  StepModel model = StepModel::kFree;
  int substeps = 1;
};

// What solving one island gave: written by the thread that solved it, read by the driver once
// every island is done
struct IslandOutcome {
  enum class Status { kSolved, kFailed, kThrew, kSkipped };
  Status status = Status::kSkipped;
  StepModel model = StepModel::kFree;
  int substeps = 1;
  double residual = 0;  // the largest over its sub-steps (failed: the last attempt's)
  int iterations = 0;
  int retries = 0;
  bool repeats = true;  // RepeatsItsStart (only sleeping reads it)
  std::vector<FailedAttempt> tried;
  SpanSums sums;              // (SpanSolver's, kept from step to step for their storage)
  std::exception_ptr thrown;  // what the model threw (kThrew)
};

// The driver's part of the StepWorkspace: vectors keep their capacity from step to step, and a
// contact copied over the last step's copy reuses its warm start's buffers
struct StepScratch {
  // FormIslandsInto's storage and its islands
  IslandScratch island_scratch;
  std::vector<Island> islands;
  // which islands sleep (PlanSleep), the awake ones in the order the threads take them, and
  // per island what solving it gave, with its state at the step's end
  SleepPlan sleep;
  std::vector<int> awake;
  std::vector<IslandOutcome> outcomes;
  std::vector<IslandState> solved;
  // per island in how many sub-steps and to what residual it was solved, and whether it
  // repeated its start (RecordRest's arguments)
  std::vector<int> island_substeps;
  std::vector<double> island_residuals;
  std::vector<char> island_repeats;
  // the bodies at the step's end
  std::vector<BodyState> next_bodies;
  // the workspace's threads and solver storage (its other parts)
  IslandThreads* threads = nullptr;
  McpWorkspace* solver = nullptr;
};

// the island's part of `state` copied into `local` (over its last contents, reusing them)
void Gather(const Island& island, const State& state, IslandState& local) {
  local.bodies.resize(island.bodies.size());
  local.contacts.resize(island.contacts.size());
  for (size_t i = 0; i < island.bodies.size(); ++i)
    local.bodies[i] = state.bodies[island.bodies[i]];
  for (size_t i = 0; i < island.contacts.size(); ++i)
    local.contacts[i] = state.contacts[island.contacts[i]];
}

// The spans of one island's step: each solved with the model's usual effort, split in two where
// that fails, each half from where the one before ended (a span solved is kept, never solved
// again at a shorter length), and given the model's last resort only where splitting did not
// solve it (at h / 2⁴, or where a half failed), so that what the usual effort solves stays as
// it was. Reads `state`, writes only `local` and `outcome`: islands on several threads at once.
class SpanSolver {
 public:
  SpanSolver(const State& state, const Island& island, const ContactModelStepper& model,
             const CancelFlag* cancel, IslandState& local, IslandOutcome& outcome)
      : state_(state),
        island_(island),
        model_(model),
        cancel_(cancel),
        local_(local),
        outcome_(outcome),
        sums_(outcome.sums) {}

  // `local` at t advanced over [t, t + h], h the step's length / 2^splits; true once solved. A
  // span that fails leaves `local` and what the solved spans summed as it found them
  bool Solve(double t, double h, int splits) {
    Start(splits);
    if (Advance(t, h, Effort::kUsual, splits)) return true;
    Restore(splits);
    if (splits < kMaxSplits) {
      if (Solve(t, h / 2, splits + 1) && Solve(t + h / 2, h / 2, splits + 1)) return true;
      Restore(splits);
    }
    if (!model_.HasLastResort()) return false;
    if (Advance(t, h, Effort::kLastResort, splits)) return true;
    Restore(splits);
    return false;
  }

  const SpanSums& sums() const { return sums_; }

 private:
  // a span's start, to return to where it fails: the step's is `state`'s, gathered again where
  // needed (the usual step, solved at once, copies nothing more); a shorter span's is kept
  void Start(int splits) {
    if (splits == 0) {
      Restore(0);
      return;
    }
    if (static_cast<int>(kept_.size()) <= splits) kept_.resize(splits + 1);
    kept_[splits] = {local_, sums_};
  }
  void Restore(int splits) {
    if (splits > 0) {
      local_ = kept_[splits].first;
      sums_ = kept_[splits].second;
      return;
    }
    Gather(island_, state_, local_);
    sums_.impulse.assign(island_.contacts.size(), Eigen::Vector4d::Zero());
    sums_.residual = 0;
    sums_.model = StepModel::kFree;
    sums_.substeps = 1;
  }

  // one attempt over [t, t + h]; what it gave added to the sums once solved
  bool Advance(double t, double h, Effort effort, int splits) {
    ThrowIfCancelled(cancel_, "the step");
    const AdvanceResult result = model_.Advance(island_, t, h, local_, effort);
    outcome_.iterations += result.iterations;
    outcome_.retries += result.retries;
    outcome_.residual = result.residual;
    outcome_.tried.insert(outcome_.tried.end(), result.tried.begin(), result.tried.end());
    if (!result.solved) return false;
    // a solved step can still overflow (e.g. the explicit gyroscopic term feeding a fast
    // spin, engine/README.md): such a state is never committed
    if (!std::all_of(local_.bodies.begin(), local_.bodies.end(),
                     [](const BodyState& b) { return IsFinite(b); })) {
      outcome_.residual = INFINITY;
      outcome_.tried.push_back({"the solved step", h, "a non-finite state"});
      return false;
    }
    sums_.residual = std::max(sums_.residual, result.residual);
    sums_.model = std::max(sums_.model, result.model);
    sums_.substeps = std::max(sums_.substeps, 1 << splits);
    for (size_t k = 0; k < island_.contacts.size(); ++k) {
      const ContactState& c = local_.contacts[k];
      sums_.impulse[k] += Eigen::Vector4d(c.p_n, c.p_t, c.p_o, c.p_r);
    }
    return true;
  }

  const State& state_;
  const Island& island_;
  const ContactModelStepper& model_;
  const CancelFlag* cancel_;
  IslandState& local_;
  IslandOutcome& outcome_;
  SpanSums& sums_;
  std::vector<std::pair<IslandState, SpanSums>> kept_;  // per split, a span's start
};

// Advances `island` from `state` into `local` by SpanSolver; a contact's impulses are the whole
// step's, its spans' sum
void SolveIsland(const Scene& scene, const State& state, const Island& island,
                 const ContactModelStepper& model, const CancelFlag* cancel, IslandState& local,
                 IslandOutcome& outcome) {
  outcome.iterations = outcome.retries = 0;
  outcome.tried.clear();
  SpanSolver spans(state, island, model, cancel, local, outcome);
  if (!spans.Solve(state.t, scene.h, 0)) {
    outcome.status = IslandOutcome::Status::kFailed;
    return;
  }
  const SpanSums& sums = spans.sums();
  outcome.status = IslandOutcome::Status::kSolved;
  outcome.model = sums.model;
  outcome.substeps = sums.substeps;
  outcome.residual = sums.residual;
  // (only sleeping reads it: a step without it pays nothing for the rule)
  outcome.repeats = !scene.solver.sleep || RepeatsItsStart(island, state, local);
  for (size_t i = 0; i < island.contacts.size(); ++i) {
    ContactState& c = local.contacts[i];
    c.p_n = sums.impulse[i][0];
    c.p_t = sums.impulse[i][1];
    c.p_o = sums.impulse[i][2];
    c.p_r = sums.impulse[i][3];
  }
}

// The awake islands in the order the threads take them: by index on one thread, else the
// dearest (most contacts and bodies) first, so that no thread is left with a large one at the end
void OrderAwake(const std::vector<Island>& islands, const SleepPlan& sleep, int threads,
                std::vector<int>& awake) {
  awake.clear();
  for (size_t i = 0; i < islands.size(); ++i) {
    if (!sleep.sleeps[i]) awake.push_back(static_cast<int>(i));
  }
  if (threads == 1 || awake.size() < 2) return;
  const auto size = [&](int i) { return islands[i].contacts.size() + islands[i].bodies.size(); };
  // (ties by index: a total order std::sort keeps without the buffer stable_sort allocates)
  std::sort(awake.begin(), awake.end(),
            [&](int a, int b) { return size(a) != size(b) ? size(a) > size(b) : a < b; });
}

// Solves the awake islands (scratch.awake) on every thread of `workspace` into scratch.solved
// and scratch.outcomes; once one fails, those after it in index order are left (the step fails
// with the first failing island's record, whichever thread met it). The lambdas capture one
// pointer, so that std::function holds them without allocating.
void SolveAwakeIslands(const Scene& scene, const State& state, const WithModel& with_model,
                       StepWorkspace& workspace, StepScratch& scratch) {
  struct Job {
    const Scene& scene;
    const State& state;
    const WithModel& with_model;
    const StepWorkspace& caller;
    StepScratch& scratch;
    const CancelFlag* cancel;
    std::atomic<int> first_failed;
  } job{scene,
        state,
        with_model,
        workspace,
        scratch,
        scratch.solver->cancel(),
        static_cast<int>(scratch.islands.size())};
  const auto solve = [&job](int i, const ContactModelStepper& model) {
    IslandOutcome& outcome = job.scratch.outcomes[i];
    outcome.status = IslandOutcome::Status::kSkipped;
    if (i > job.first_failed.load(std::memory_order_relaxed)) return;
    try {
      SolveIsland(job.scene, job.state, job.scratch.islands[i], model, job.cancel,
                  job.scratch.solved[i], outcome);
    } catch (...) {
      outcome.thrown = std::current_exception();
      outcome.status = IslandOutcome::Status::kThrew;
    }
    if (outcome.status == IslandOutcome::Status::kSolved) return;
    for (int seen = job.first_failed.load();
         i < seen && !job.first_failed.compare_exchange_weak(seen, i);) {
    }
  };
  scratch.threads->ForEach(
      scratch.awake, workspace,
      [&job, &solve](StepWorkspace& thread_workspace, const IslandThreads::TakeItem& take) {
        // (the caller's own workspace already watches the flag)
        if (&thread_workspace != &job.caller)
          thread_workspace.Part<McpWorkspace>().StopOn(job.cancel);
        const auto take_and_solve = [&take, &solve](const ContactModelStepper& model) {
          for (int i; take(i);) solve(i, model);
        };
        job.with_model(thread_workspace, take_and_solve);
      });
}

// The islands' outcomes in index order into `report`, each island's bodies at the step's end
// into `next_bodies` (a sleeping island replays its last step); the first island that failed
// fails the step
void ReadOutcomes(const Scene& scene, const State& state, StepScratch& scratch,
                  StepReport& report) {
  const std::vector<Island>& islands = scratch.islands;
  const SleepPlan& sleep = scratch.sleep;
  for (size_t island_index = 0; island_index < islands.size(); ++island_index) {
    const Island& island = islands[island_index];
    IslandState& local = scratch.solved[island_index];
    // a sleeping island replays its last step: its bodies' poses advance, nothing else changes
    if (sleep.sleeps[island_index]) {
      local.bodies.resize(island.bodies.size());
      for (size_t i = 0; i < island.bodies.size(); ++i) {
        local.bodies[i] = state.bodies[island.bodies[i]];
        report.models[island.bodies[i]] = state.rest.models[island.bodies[i]];
        report.residual = std::max(report.residual, state.rest.residuals[island.bodies[i]]);
      }
      ReplayStep(scene.h, local.bodies);
      ++report.sleeping_islands;
      report.sleeping_bodies += static_cast<int>(island.bodies.size());
      continue;
    }
    IslandOutcome& outcome = scratch.outcomes[island_index];
    if (outcome.status == IslandOutcome::Status::kThrew)
      std::rethrow_exception(std::exchange(outcome.thrown, nullptr));
    // (a skipped island comes after a failed one)
    if (outcome.status != IslandOutcome::Status::kSolved) {
      StepFailure failure;
      failure.model = ContactModelName(scene.model);
      failure.t = state.t;
      for (int b : island.bodies) failure.bodies.push_back(scene.bodies[b].name);
      failure.residual = outcome.residual;
      failure.tolerance = scene.solver.tolerance;
      failure.tried = std::move(outcome.tried);
      throw SolverFailure(std::move(failure));
    }
    report.iterations += outcome.iterations;
    report.retries += outcome.retries;
    for (int b : island.bodies) report.models[b] = outcome.model;
    // the hull model over parts says so
    if (outcome.model == StepModel::kHull) {
      for (int k : island.contacts) {
        const ContactPair& pair = scene.contacts[k];
        if (pair.part >= 0) report.models[pair.body] = StepModel::kParts;
        if (pair.other_part >= 0 && !scene.bodies[pair.other_body].IsKinematic())
          report.models[pair.other_body] = StepModel::kParts;
      }
    }
    scratch.island_substeps[island_index] = outcome.substeps;
    scratch.island_residuals[island_index] = outcome.residual;
    scratch.island_repeats[island_index] = outcome.repeats;
    report.substeps = std::max(report.substeps, outcome.substeps);
    report.residual = std::max(report.residual, outcome.residual);
  }

  // kinematic bodies: the prescribed pose at the step's end (never a sum of c + h v, which
  // drifts) and the step's twist (a motion that throws leaves `state` as it was)
  std::vector<BodyState>& next_bodies = scratch.next_bodies;
  next_bodies = state.bodies;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    if (!body.IsKinematic()) continue;
    const KinematicMotion::Twist twist = body.motion->StepTwist(state.t, scene.h);
    const KinematicPose end = body.motion->PoseAt(static_cast<double>(state.steps + 1) * scene.h);
    next_bodies[b] = {end.p, end.q, twist.v, twist.w};
  }
  for (size_t i = 0; i < islands.size(); ++i) {
    for (size_t j = 0; j < islands[i].bodies.size(); ++j)
      next_bodies[islands[i].bodies[j]] = scratch.solved[i].bodies[j];
  }
}

// Whether every pair the islands left out as staying apart (IslandScratch::apart) is apart at the
// step's end; those that are not are marked to be kept in the step (IslandScratch::kept)
bool ApartPairsEndApart(const Scene& scene, StepScratch& scratch) {
  IslandScratch& islands = scratch.island_scratch;
  bool all_apart = true;
  for (int k : islands.apart) {
    const ContactPair& pair = scene.contacts[k];
    const double size =
        std::max(islands.reach.size[pair.body], islands.reach.size[pair.other_body]);
    if (EndsApart(scene, k, scratch.next_bodies[pair.body], scratch.next_bodies[pair.other_body],
                  size))
      continue;
    islands.kept.resize(scene.contacts.size(), false);
    islands.kept[k] = true;
    all_apart = false;
  }
  return all_apart;
}

}  // namespace

StepReport StepIslands(const Scene& scene, State& state, const WithModel& with_model,
                       StepWorkspace& workspace) {
  StepScratch& scratch = workspace.Part<StepScratch>();
  // (looked up once: the workspace keeps its parts where they are)
  if (scratch.threads == nullptr) {
    scratch.threads = &IslandThreadsOf(workspace);
    scratch.solver = &workspace.Part<McpWorkspace>();
  }
  // the step's results, written into `state` only once every island is solved (a failure leaves
  // it as it was); the contacts' states are not copied as a whole: with every pair of bodies a
  // potential contact they outnumber the bodies by far (2,016 pairs for 64 boxes)
  std::vector<Island>& islands = scratch.islands;
  const SleepPlan& sleep = scratch.sleep;
  // the islands solved without the pairs that stay apart; a pair found not apart at the step's
  // end is kept in it and the step solved again (engine/README.md, "Pairs apart at both ends of
  // the step"); the work of every pass is counted
  scratch.island_scratch.kept.clear();
  StepReport report;
  int earlier_iterations = 0, earlier_retries = 0;
  for (;;) {
    report = StepReport{};
    report.converged = true;
    report.models.assign(scene.bodies.size(), StepModel::kKinematic);
    FormIslandsInto(scene, state, scratch.island_scratch, islands);
    scratch.solved.resize(islands.size());
    scratch.outcomes.resize(islands.size());
    PlanSleep(scene, state, islands, scratch.sleep);
    scratch.island_substeps.assign(islands.size(), 1);
    scratch.island_residuals.assign(islands.size(), 0.0);
    // (a replay repeats its start)
    scratch.island_repeats.assign(islands.size(), true);
    OrderAwake(islands, sleep, scratch.threads->threads(), scratch.awake);
    SolveAwakeIslands(scene, state, with_model, workspace, scratch);
    ReadOutcomes(scene, state, scratch, report);
    if (ApartPairsEndApart(scene, scratch)) break;
    earlier_iterations += report.iterations;
    earlier_retries += report.retries;
  }
  report.iterations += earlier_iterations;
  report.retries += earlier_retries;
  std::vector<IslandState>& solved = scratch.solved;

  // every island solved: the step is committed (copied over the state's own storage)
  state.bodies.swap(scratch.next_bodies);
  for (size_t i = 0; i < islands.size(); ++i) {
    const Island& island = islands[i];
    // (a replay leaves its contacts as they are)
    if (sleep.sleeps[i]) continue;
    // copied over the state's contacts, warm starts into their own storage (swapping would move
    // each warm start three times: it lives inside its contact)
    for (size_t j = 0; j < island.contacts.size(); ++j)
      state.contacts[island.contacts[j]] = solved[i].contacts[j];
  }
  // contacts in no island: their bodies are apart for the whole step. Those that were in none at
  // the last step either were cleared then (the record says which; most of a body of parts'
  // pairs, whose states are not read again)
  const std::vector<char>& was_in_step = state.rest.in_step;
  const auto clear_left = [&](size_t k) {
    if (sleep.in_step[k]) return;
    ContactState& c = state.contacts[k];
    // (most are clear already, +0 to the bit: a pile's far pairs, parts away from the other
    // body)
    const auto clear = [](double x) { return x == 0 && !std::signbit(x); };
    if (c.warm_start.empty() && clear(c.p_n) && clear(c.p_t) && clear(c.p_o) && clear(c.p_r) &&
        clear(c.sigma))
      return;
    c.p_n = c.p_t = c.p_o = c.p_r = c.sigma = 0;
    c.warm_start.Reset();
  };
  if (was_in_step.size() == scene.contacts.size()) {
    ForEachDifference(sleep.in_step, was_in_step, clear_left);
  } else {
    for (size_t k = 0; k < scene.contacts.size(); ++k) clear_left(k);
  }
  // without sleeping no counts are kept: one made while it was off would let an island that
  // turned it on sleep on counts it never earned
  if (scene.solver.sleep) {
    RecordRest(scene, islands, sleep, report.models, scratch.island_substeps,
               scratch.island_repeats, scratch.island_residuals, state);
  } else {
    RecordInStepOnly(sleep, state.rest);
  }
  AdvanceTime(scene.h, state);
  return report;
}

}  // namespace ecpsim::engine
