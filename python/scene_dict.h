#pragma once
// Scenes built from Python lists and dicts for the `ecpsim` module (`make_scene`): bodies,
// obstacles, friction and loads, checked by ValidateScene as a file's are.

#include <memory>
#include <string>

#include <pybind11/pybind11.h>

#include "engine/scene_io/loaded_scene.h"

namespace ecpsim::python {

/// The scene of `make_scene` (docs/python.md): `bodies` (dicts of shape, mass, pose,
/// velocities, friction), `obstacles` (None: the ground), step `h` and `duration` (s),
/// `gravity` (m/s²), the ground's `friction`, `loads` and the contact `model`; the output settings
/// are the defaults and there are no warnings. The scene passes engine::ValidateScene.
/// @throws InputError naming the key path, the value and what was expected, e.g.
///         `bodies[0].friction.mu = -1: expected ...`; ValidateScene's problems are named at the
///         first of their keys that the arguments give (`friction.mu` for the default ground's
///         friction, `box` for a box's size), else at the scene's key, with the scene's value.
std::shared_ptr<engine::LoadedScene> MakeScene(const pybind11::list& bodies,
                                               const pybind11::object& obstacles, double h,
                                               double duration, const pybind11::handle& gravity,
                                               const pybind11::object& friction,
                                               const pybind11::object& loads,
                                               const std::string& model);

}  // namespace ecpsim::python
