#include "engine/step_driver.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include "engine/island_sleep.h"
#include "engine/islands.h"

namespace ecpsim::engine {
namespace {

// the sub-step ladder: the step at h, then in 2, 4 and 16 equal parts (engine/README.md: hard
// impacts and bodies far smaller than g h² need the last rung)
constexpr int kSubsteps[] = {1, 2, 4, 16};
constexpr int kLadderLength = static_cast<int>(std::size(kSubsteps));

// The driver's part of the StepWorkspace: vectors keep their capacity from step to step, and a
// contact copied over the last step's copy reuses its warm start's buffers
struct StepScratch {
  // FormIslandsInto's storage and its islands
  IslandScratch island_scratch;
  std::vector<Island> islands;
  // which islands sleep (PlanSleep), and per island in how many sub-steps and to what residual
  // it was solved, and whether it repeated its start
  SleepPlan sleep;
  std::vector<int> island_substeps;
  std::vector<double> island_residuals;
  std::vector<char> island_repeats;
  // StepIslands: per island its state at the step's end, its contacts' impulses summed over the
  // sub-steps; the bodies at the step's end
  std::vector<IslandState> solved;
  std::vector<Eigen::Vector4d> impulse;
  std::vector<BodyState> next_bodies;
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

}  // namespace

StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model,
                       StepWorkspace& workspace) {
  StepScratch& scratch = workspace.Part<StepScratch>();
  StepReport report;
  report.converged = true;
  report.models.assign(scene.bodies.size(), StepModel::kKinematic);
  // the step's results, written into `state` only once every island is solved (a failure leaves
  // it as it was); the contacts' states are not copied as a whole: with every pair of bodies a
  // potential contact they outnumber the bodies by far (2,016 pairs for 64 boxes)
  std::vector<Island>& islands = scratch.islands;
  FormIslandsInto(scene, state, scratch.island_scratch, islands);
  std::vector<IslandState>& solved = scratch.solved;
  solved.resize(islands.size());
  const SleepPlan& sleep = scratch.sleep;
  PlanSleep(scene, state, islands, scratch.sleep);
  scratch.island_substeps.assign(islands.size(), 1);
  scratch.island_residuals.assign(islands.size(), 0.0);
  // (a replay repeats its start)
  scratch.island_repeats.assign(islands.size(), true);

  for (size_t island_index = 0; island_index < islands.size(); ++island_index) {
    const Island& island = islands[island_index];
    IslandState& local = solved[island_index];
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
    std::vector<FailedAttempt> tried;
    double residual = 0;
    bool island_solved = false;
    // the sub-step ladder with the model's usual effort; only where that fails at every length,
    // again with its last resort (if it has one), so that what the usual effort solves stays as
    // it was
    const int attempts = (model.HasLastResort() ? 2 : 1) * kLadderLength;
    for (int attempt = 0; attempt < attempts && !island_solved; ++attempt) {
      const Effort effort = attempt < kLadderLength ? Effort::kUsual : Effort::kLastResort;
      const int substeps = kSubsteps[attempt % kLadderLength];
      Gather(island, state, local);
      const double h = scene.h / substeps;
      double island_residual = 0;
      StepModel island_model = StepModel::kFree;
      bool ok = true;
      // a contact's impulses are the whole step's: the sub-steps' sum
      std::vector<Eigen::Vector4d>& impulse = scratch.impulse;
      impulse.assign(island.contacts.size(), Eigen::Vector4d::Zero());
      for (int i = 0; i < substeps && ok; ++i) {
        const AdvanceResult result = model.Advance(island, state.t + i * h, h, local, effort);
        for (size_t k = 0; k < island.contacts.size(); ++k) {
          const ContactState& c = local.contacts[k];
          impulse[k] += Eigen::Vector4d(c.p_n, c.p_t, c.p_o, c.p_r);
        }
        report.iterations += result.iterations;
        report.retries += result.retries;
        residual = result.residual;
        island_residual = std::max(island_residual, result.residual);
        island_model = std::max(island_model, result.model);
        tried.insert(tried.end(), result.tried.begin(), result.tried.end());
        ok = result.solved;
        // a solved step can still overflow (e.g. the explicit gyroscopic term feeding a fast
        // spin, engine/README.md): such a state is never committed
        if (ok && !std::all_of(local.bodies.begin(), local.bodies.end(),
                               [](const BodyState& b) { return IsFinite(b); })) {
          ok = false;
          residual = INFINITY;
          tried.push_back({"the solved step", h, "a non-finite state"});
        }
      }
      if (!ok) continue;
      for (int b : island.bodies) report.models[b] = island_model;
      // the hull model over parts says so
      if (island_model == StepModel::kHull) {
        for (int k : island.contacts) {
          const ContactPair& pair = scene.contacts[k];
          if (pair.part >= 0) report.models[pair.body] = StepModel::kParts;
          if (pair.other_part >= 0 && !scene.bodies[pair.other_body].IsKinematic())
            report.models[pair.other_body] = StepModel::kParts;
        }
      }
      scratch.island_substeps[island_index] = substeps;
      scratch.island_residuals[island_index] = island_residual;
      // (only sleeping reads it: a step without it pays nothing for the rule)
      if (scene.solver.sleep)
        scratch.island_repeats[island_index] = RepeatsItsStart(island, state, local);
      for (size_t i = 0; i < island.contacts.size(); ++i) {
        ContactState& c = local.contacts[i];
        c.p_n = impulse[i][0];
        c.p_t = impulse[i][1];
        c.p_o = impulse[i][2];
        c.p_r = impulse[i][3];
      }
      report.substeps = std::max(report.substeps, substeps);
      report.residual = std::max(report.residual, island_residual);
      island_solved = true;
    }
    if (!island_solved) {
      StepFailure failure;
      failure.model = ContactModelName(scene.model);
      failure.t = state.t;
      for (int b : island.bodies) failure.bodies.push_back(scene.bodies[b].name);
      failure.residual = residual;
      failure.tolerance = scene.solver.tolerance;
      failure.tried = std::move(tried);
      throw SolverFailure(std::move(failure));
    }
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

  // every island solved: the step is committed (copied over the state's own storage)
  state.bodies.swap(next_bodies);
  for (size_t i = 0; i < islands.size(); ++i) {
    const Island& island = islands[i];
    for (size_t j = 0; j < island.bodies.size(); ++j)
      state.bodies[island.bodies[j]] = solved[i].bodies[j];
    // (a replay leaves its contacts as they are)
    if (sleep.sleeps[i]) continue;
    // copied over the state's contacts, warm starts into their own storage (swapping would move
    // each warm start three times: it lives inside its contact)
    for (size_t j = 0; j < island.contacts.size(); ++j)
      state.contacts[island.contacts[j]] = solved[i].contacts[j];
  }
  // contacts in no island: their bodies are apart for the whole step
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    if (sleep.in_step[k]) continue;
    ContactState& c = state.contacts[k];
    // (most are clear already, +0 to the bit: a pile's far pairs, parts away from the other
    // body)
    const auto clear = [](double x) { return x == 0 && !std::signbit(x); };
    if (c.warm_start.empty() && clear(c.p_n) && clear(c.p_t) && clear(c.p_o) && clear(c.p_r) &&
        clear(c.sigma))
      continue;
    c.p_n = c.p_t = c.p_o = c.p_r = c.sigma = 0;
    c.warm_start.Reset();
  }
  // without sleeping no record is kept: one made while it was off would let an island that
  // turned it on sleep on counts it never earned
  if (scene.solver.sleep) {
    RecordRest(scene, islands, sleep, report.models, scratch.island_substeps,
               scratch.island_repeats, scratch.island_residuals, state);
  } else if (!state.rest.steps.empty()) {
    state.rest = RestRecord{};
  }
  AdvanceTime(scene.h, state);
  return report;
}

}  // namespace ecpsim::engine
