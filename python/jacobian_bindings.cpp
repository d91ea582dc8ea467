#include "python/jacobian_bindings.h"

#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "engine/step_sensitivity.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

// the flags and diagnostics of a StepJacobians as a dict
py::dict Flags(const engine::Scene& scene, const engine::StepSensitivity& s) {
  py::dict flags;
  flags["degenerate"] = s.degenerate;
  flags["isolated"] = s.isolated;
  flags["method"] = s.method;
  flags["residual"] = s.residual;
  flags["A_determined"] = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>(s.A_determined);
  flags["B_determined"] = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>(s.B_determined);
  py::list islands;
  for (const engine::IslandSensitivity& island : s.islands) {
    py::dict d;
    py::list names;
    for (int b : island.bodies) names.append(scene.bodies[b].name);
    d["bodies"] = names;
    d["unknowns"] = island.unknowns;
    d["rank"] = island.rank;
    d["degenerate_pairs"] = island.degenerate_pairs;
    d["residual"] = island.residual;
    islands.append(d);
  }
  flags["islands"] = islands;
  return flags;
}

// what step_jacobians returns: the sensitivities and the scene's body names they refer to
struct StepJacobians {
  engine::StepSensitivity sensitivity;
  std::vector<std::string> bodies;
  py::dict flags;
};

}  // namespace

void BindJacobians(py::class_<PySimulation>& sim) {
  py::class_<StepJacobians>(
      sim, "StepJacobians",
      "The derivatives of one step: unpacks as A, B. A = ∂x⁺/∂x (12 n × 12 n), B = ∂x⁺/∂u "
      "(12 n × 6 n) for the n dynamic bodies of `bodies`, each with state coordinates [p (m), θ "
      "(rad), v (m/s), ω (rad/s)] (world frame; θ a turn applied in the world frame, "
      "q = exp(θ) ⊗ q₀) and inputs [force (N) at the CM, torque (N·m)] over the step. `flags`: "
      "{degenerate, isolated, method, residual, islands} (docs/python.md, \"Derivatives of a "
      "step\").")
      .def_property_readonly(
          "A", [](const StepJacobians& j) { return j.sensitivity.A; }, "(12 n, 12 n) ∂x⁺/∂x.")
      .def_property_readonly(
          "B", [](const StepJacobians& j) { return j.sensitivity.B; }, "(12 n, 6 n) ∂x⁺/∂u.")
      .def_property_readonly(
          "bodies", [](const StepJacobians& j) { return j.bodies; },
          "Names of the dynamic bodies, in the order of the blocks.")
      .def_property_readonly(
          "flags", [](const StepJacobians& j) { return j.flags; },
          "degenerate: a complementarity pair had both members ≈ 0 (A, B are one element of the "
          "generalized Jacobian); isolated: every island's Newton matrix had full rank (False: "
          "minimum-norm solution); method; residual (the largest island measure at the root); "
          "islands: per island bodies, unknowns, rank, degenerate_pairs, residual.")
      .def("__len__", [](const StepJacobians&) { return 2; })
      .def("__iter__",
           [](const StepJacobians& j) {
             return py::iter(py::make_tuple(j.sensitivity.A, j.sensitivity.B));
           })
      .def("__getitem__", [](const StepJacobians& j, int i) -> py::object {
        if (i == 0 || i == -2) return py::cast(j.sensitivity.A);
        if (i == 1 || i == -1) return py::cast(j.sensitivity.B);
        throw py::index_error("StepJacobians holds A and B: index 0 or 1");
      });

  sim.def(
      "step_jacobians",
      [](PySimulation& self) {
        StepJacobians out;
        {
          py::gil_scoped_release release;
          const std::lock_guard<std::mutex> lock(self.mutex);
          // the next step as step() would take it: its pending wrenches are loads of the scene
          // (copied only where there are any)
          const std::vector<engine::Load>& pending = self.sim.pending_wrenches();
          std::optional<engine::Scene> with_pending;
          if (!pending.empty()) {
            with_pending = self.sim.scene();
            with_pending->loads.insert(with_pending->loads.end(), pending.begin(), pending.end());
          }
          const engine::Scene& scene = with_pending ? *with_pending : self.sim.scene();
          // (a workspace is memory, never state: a fresh one steps as the Simulation's own)
          engine::StepWorkspace workspace;
          out.sensitivity = engine::ComputeStepSensitivity(scene, self.sim.state(), workspace);
          for (int b : out.sensitivity.bodies) out.bodies.push_back(scene.bodies[b].name);
        }
        out.flags = Flags(self.sim.scene(), out.sensitivity);
        return out;
      },
      "The derivatives of the next step at the current state and pending wrenches, by the "
      "implicit function theorem on each island's converged MNCP; the simulation is not "
      "advanced. Returns a Simulation.StepJacobians: A, B = sim.step_jacobians(); its `flags` "
      "say whether the contact mode was degenerate or the solution not isolated.\n"
      "Raises ModelInvalid for the multipatch and point models and for a step that needed "
      "sub-steps; SolverFailure as step().");
}

}  // namespace ecpsim::python
