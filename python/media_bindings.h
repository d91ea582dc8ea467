#pragma once
// Videos and image comparison for the `ecpsim` module, as the CLI makes them:
// Simulation.record and Simulation.recorder (`ecpsim run --video`) and compare_images
// (`ecpsim compare`). Reference: docs/python.md, "Videos" and "Comparing images".

#include <pybind11/pybind11.h>

#include "python/py_simulation.h"

namespace ecpsim::python {

/// Adds Simulation.record, Simulation.recorder, the Recorder class and compare_images to `m`.
void BindMedia(pybind11::module_& m, pybind11::class_<PySimulation>& sim);

}  // namespace ecpsim::python
