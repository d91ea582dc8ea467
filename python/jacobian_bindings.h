#pragma once
// Simulation.step_jacobians(): the derivatives of the next step (engine/step_sensitivity.h),
// bound in a file of its own.

#include <pybind11/pybind11.h>

#include "python/py_simulation.h"

namespace ecpsim::python {

/// Adds step_jacobians() and its result class, Simulation.StepJacobians, to `sim`.
void BindJacobians(pybind11::class_<PySimulation>& sim);

}  // namespace ecpsim::python
