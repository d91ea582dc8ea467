#pragma once
// The bindings of batched rollouts and domain randomization (issue 32): `ecpsim.rollout` and the
// Simulation's set_mass, set_inertia and set_friction. Reference: docs/python.md.

#include <pybind11/pybind11.h>

#include "python/py_simulation.h"

namespace ecpsim::python {

/// Adds `rollout` to module `m` and set_mass, set_inertia, set_friction to class `sim`; called
/// once from PYBIND11_MODULE, after the module's exceptions are registered (rollout raises them
/// with attributes of its own).
void BindRollout(pybind11::module_& m, pybind11::class_<PySimulation>& sim);

}  // namespace ecpsim::python
