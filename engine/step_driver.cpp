#include "engine/step_driver.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

namespace ecpsim::engine {
namespace {

// the sub-step ladder: the step at h, then in 2, 4 and 16 equal parts (engine/README.md: hard
// impacts and bodies far smaller than g h² need the last rung)
constexpr int kSubsteps[] = {1, 2, 4, 16};

IslandState Gather(const Island& island, const State& state) {
  IslandState local;
  for (int b : island.bodies) local.bodies.push_back(state.bodies[b]);
  for (int k : island.contacts) local.contacts.push_back(state.contacts[k]);
  return local;
}

std::string BodyNames(const Scene& scene, const Island& island) {
  std::string names;
  for (int b : island.bodies)
    names += fmt::format("{}'{}'", names.empty() ? "" : ", ", scene.bodies[b].name);
  return names;
}

}  // namespace

std::vector<Island> FormIslands(const Scene& scene) {
  std::vector<Island> islands(scene.bodies.size());
  for (size_t b = 0; b < scene.bodies.size(); ++b) islands[b].bodies = {static_cast<int>(b)};
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    islands[scene.contacts[k].body].contacts.push_back(static_cast<int>(k));
  return islands;
}

StepReport StepIslands(const Scene& scene, State& state, const ContactModelStepper& model) {
  StepReport report;
  report.converged = true;
  State next = state;

  for (const Island& island : FormIslands(scene)) {
    std::string tried;
    double residual = 0;
    bool solved = false;
    for (int substeps : kSubsteps) {
      IslandState local = Gather(island, state);
      const double h = scene.h / substeps;
      double island_residual = 0;
      bool ok = true;
      for (int i = 0; i < substeps && ok; ++i) {
        AdvanceResult result = model.Advance(island, state.t + i * h, h, local);
        report.iterations += result.iterations;
        report.retries += result.retries;
        residual = result.residual;
        island_residual = std::max(island_residual, result.residual);
        if (!result.tried.empty())
          tried += fmt::format("{}{}", tried.empty() ? "" : "; ", result.tried);
        ok = result.solved;
        // a solved step can still overflow (e.g. the explicit gyroscopic term feeding a fast
        // spin, engine/README.md): such a state is never committed
        if (ok && !std::all_of(local.bodies.begin(), local.bodies.end(),
                               [](const BodyState& b) { return IsFinite(b); })) {
          ok = false;
          residual = INFINITY;
          tried += fmt::format("{}a non-finite state (h = {:g} s)", tried.empty() ? "" : "; ", h);
        }
      }
      if (!ok) continue;
      for (size_t i = 0; i < island.bodies.size(); ++i)
        next.bodies[island.bodies[i]] = local.bodies[i];
      for (size_t i = 0; i < island.contacts.size(); ++i)
        next.contacts[island.contacts[i]] = local.contacts[i];
      report.substeps = std::max(report.substeps, substeps);
      report.residual = std::max(report.residual, island_residual);
      solved = true;
      break;
    }
    if (!solved) {
      throw SolverFailure(fmt::format(
          "{}solver failed at t = {:.6g} s on body {}: residual {:.3g} > tolerance {:.3g}; "
          "tried {}",
          model.MessagePrefix(), state.t, BodyNames(scene, island), residual,
          scene.solver.tolerance, tried));
    }
  }

  state.bodies = std::move(next.bodies);
  state.contacts = std::move(next.contacts);
  AdvanceTime(scene.h, state);
  return report;
}

}  // namespace ecpsim::engine
