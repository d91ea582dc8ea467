#include "engine/island_sleep.h"

#include <algorithm>
#include <cmath>

#include "engine/loads.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

// whether `record` is the memory of a state of `scene` (an empty or foreign one: every body awake)
bool Fits(const RestRecord& record, const Scene& scene) {
  return record.steps.size() == scene.bodies.size() &&
         record.models.size() == scene.bodies.size() &&
         record.residuals.size() == scene.bodies.size() &&
         record.in_step.size() == scene.contacts.size();
}

// whether nothing but gravity and the body's contacts acts on `body` differently over the step
// [t, t + h] than over the one before: its loads and impulses sum to the same bits at the same
// orientation (a load that changes with t, a window that opens or closes, an impulse's instant)
bool LoadsUnchanged(const Scene& scene, const State& state, int body) {
  if (scene.loads.empty() && scene.impulses.empty()) return true;
  const Eigen::Matrix3d R = state.bodies[body].Q_WB.toRotationMatrix();
  const double last_t = static_cast<double>(state.steps - 1) * scene.h;
  return AppliedImpulse(scene.loads, scene.impulses, body, state.t, scene.h, R) ==
         AppliedImpulse(scene.loads, scene.impulses, body, last_t, scene.h, R);
}

// whether island `island` meets the rule's preconditions (SleepPlan::steady)
bool Steady(const Scene& scene, const State& state, const Island& island,
            const std::vector<char>& touched) {
  for (int b : island.bodies) {
    if (touched[b] || scene.bodies[b].IsJaw() || !LoadsUnchanged(scene, state, b)) return false;
  }
  for (int k : island.contacts) {
    const ContactPair& pair = scene.contacts[k];
    if (pair.WithBody() && scene.bodies[pair.other_body].IsKinematic()) return false;
  }
  return true;
}

}  // namespace

bool AtRest(const Body& body, const BodyState& state, double h) {
  // the body's length scale: its radius of gyration, as BodyScales' (mncp_scaling.h)
  const double length = std::sqrt(body.inertia.trace() / body.mass);
  return h * state.v_WB.norm() <= kRestFraction * length &&
         h * state.w_WB.norm() <= kRestFraction;
}

void PlanSleep(const Scene& scene, const State& state, const std::vector<Island>& islands,
               SleepPlan& plan) {
  plan.steady.assign(islands.size(), false);
  plan.sleeps.assign(islands.size(), false);
  plan.in_step.assign(scene.contacts.size(), false);
  for (const Island& island : islands) {
    for (int k : island.contacts) plan.in_step[k] = true;
  }
  // the first step has no last step to compare with
  if (!scene.solver.sleep || state.steps == 0 || !Fits(state.rest, scene)) return;
  // a contact that entered or left the step (the broad phase proposed it, or its bodies moved
  // apart) touches the islands of its bodies: a body approaching, an island merged or split
  plan.touched.assign(scene.bodies.size(), false);
  ForEachDifference(plan.in_step, state.rest.in_step, [&](size_t k) {
    const ContactPair& pair = scene.contacts[k];
    plan.touched[pair.body] = true;
    if (pair.WithBody()) plan.touched[pair.other_body] = true;
  });
  for (size_t i = 0; i < islands.size(); ++i) {
    const Island& island = islands[i];
    // an island moving at the start neither sleeps nor repeats its start at rest, whatever its
    // loads: they are evaluated only for islands at rest (the desk's, every step)
    const auto at_rest = [&](int b) { return AtRest(scene.bodies[b], state.bodies[b], scene.h); };
    plan.steady[i] = std::all_of(island.bodies.begin(), island.bodies.end(), at_rest) &&
                     Steady(scene, state, island, plan.touched);
    if (!plan.steady[i]) continue;
    bool sleeps = true;
    for (int b : island.bodies) {
      const std::int64_t rest = state.rest.steps[b];
      sleeps = sleeps && rest >= kStepsToSleep && rest % kSleepCheckSteps != 0;
    }
    plan.sleeps[i] = sleeps;
  }
}

bool RepeatsItsStart(const Island& island, const State& state, const IslandState& end) {
  for (size_t i = 0; i < island.bodies.size(); ++i) {
    const BodyState& start = state.bodies[island.bodies[i]];
    if (end.bodies[i].v_WB != start.v_WB || end.bodies[i].w_WB != start.w_WB) return false;
  }
  for (size_t i = 0; i < island.contacts.size(); ++i) {
    const ContactState& start = state.contacts[island.contacts[i]];
    const ContactState& c = end.contacts[i];
    if (c.a1 != start.a1 || c.a2 != start.a2 || c.p_n != start.p_n || c.p_t != start.p_t ||
        c.p_o != start.p_o || c.p_r != start.p_r || c.sigma != start.sigma) {
      return false;
    }
  }
  return true;
}

void ReplayStep(double h, std::vector<BodyState>& bodies) {
  for (BodyState& body : bodies) {
    body.p_WB += h * body.v_WB;
    body.Q_WB = IntegrateOrientation(body.Q_WB, body.w_WB, h);
  }
}

void RecordRest(const Scene& scene, const std::vector<Island>& islands, const SleepPlan& plan,
                const std::vector<StepModel>& body_models,
                const std::vector<int>& island_substeps, const std::vector<char>& island_repeats,
                const std::vector<double>& island_residuals, State& state) {
  RestRecord& rest = state.rest;
  if (!Fits(rest, scene)) {
    rest.steps.assign(scene.bodies.size(), 0);
    rest.models.assign(scene.bodies.size(), StepModel::kFree);
    rest.residuals.assign(scene.bodies.size(), 0.0);
    rest.in_step.assign(scene.contacts.size(), false);
  }
  for (size_t i = 0; i < islands.size(); ++i) {
    const Island& island = islands[i];
    bool at_rest = plan.steady[i] && island_substeps[i] == 1 && island_repeats[i];
    // (the island's bodies share their count since its contacts last changed; the least after
    // a record of another run)
    std::int64_t steps = INT64_MAX;
    for (int b : island.bodies) {
      at_rest = at_rest && AtRest(scene.bodies[b], state.bodies[b], scene.h);
      steps = std::min(steps, rest.steps[b]);
    }
    for (int b : island.bodies) {
      rest.steps[b] = at_rest ? steps + 1 : 0;
      if (plan.sleeps[i]) continue;
      rest.models[b] = body_models[b];
      rest.residuals[b] = island_residuals[i];
    }
  }
  rest.in_step = plan.in_step;
}

void RecordInStepOnly(const SleepPlan& plan, RestRecord& rest) {
  rest.steps.clear();
  rest.models.clear();
  rest.residuals.clear();
  rest.in_step = plan.in_step;
}

}  // namespace ecpsim::engine
