#include "engine/step_driver.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace ecpsim::engine {
StepReport StepEveryBody(const Scene& scene, State& state, const std::string& model_prefix,
                         const AdvanceBody& advance) {
  StepReport report;
  report.converged = true;
  std::vector<BodyState> next_bodies = state.bodies;
  std::vector<ContactState> next_contacts = state.contacts;

  for (int b = 0; b < static_cast<int>(scene.bodies.size()); ++b) {
    std::vector<int> contact_ids;
    for (int k = 0; k < static_cast<int>(scene.contacts.size()); ++k)
      if (scene.contacts[k].body == b) contact_ids.push_back(k);

    // the ladder at h, then 2 sub-steps of h/2, 4 of h/4, 16 of h/16 (engine/README.md)
    std::string tried;
    double residual = 0;
    bool solved = false;
    for (int substeps : {1, 2, 4, 16}) {
      BodyState body = state.bodies[b];
      std::vector<ContactState> contacts;
      for (int id : contact_ids) contacts.push_back(state.contacts[id]);
      const double h = scene.h / substeps;
      bool ok = true;
      for (int i = 0; i < substeps && ok; ++i) {
        ok = advance(b, contact_ids, state.t + i * h, h, body, contacts, report, residual, tried);
        // a solved step can still overflow (e.g. the explicit gyroscopic term feeding a fast
        // spin, engine/README.md): such a state is never committed
        if (ok && !IsFinite(body)) {
          ok = false;
          residual = INFINITY;
          tried += fmt::format("{}a non-finite state (h = {:g} s)", tried.empty() ? "" : "; ", h);
        }
      }
      if (!ok) continue;
      next_bodies[b] = body;
      for (size_t k = 0; k < contact_ids.size(); ++k) next_contacts[contact_ids[k]] = contacts[k];
      report.substeps = std::max(report.substeps, substeps);
      report.residual = std::max(report.residual, residual);
      solved = true;
      break;
    }
    if (!solved) {
      throw SolverFailure(fmt::format(
          "{}solver failed at t = {:.6g} s on body '{}': residual {:.3g} > tolerance {:.3g}; "
          "tried {}",
          model_prefix, state.t, scene.bodies[b].name, residual, scene.solver.tolerance, tried));
    }
  }

  state.bodies = std::move(next_bodies);
  state.contacts = std::move(next_contacts);
  AdvanceTime(scene.h, state);
  return report;
}

}  // namespace ecpsim::engine
