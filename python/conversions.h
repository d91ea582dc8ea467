#pragma once
// Conversions between Python values and the libraries' types for the `ecpsim` module: numpy
// arrays of vectors and matrices, numbers and vectors from any Python sequence, bodies and
// grippers by name or index, and Python overrides as the CLI's `--set` strings.

#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/scene_io/loaded_scene.h"
#include "render/frame_input.h"

namespace ecpsim::python {

/// A numpy array of `shape` holding a copy of `data` (row-major).
pybind11::array_t<double> Array(const double* data, std::vector<pybind11::ssize_t> shape);
/// A numpy (3,) array.
pybind11::array_t<double> Array(const Eigen::Vector3d& v);
/// A numpy (3, 3) array, rows as the matrix's.
pybind11::array_t<double> Array(const Eigen::Matrix3d& m);

/// Any sequence of 3 numbers (list, tuple, numpy array) as a vector.
/// @throws InputError naming `what`.
Eigen::Vector3d ToVector3(const pybind11::handle& value, const std::string& what);

/// A number from Python.
/// @throws InputError naming `what`.
double ToDouble(const pybind11::handle& value, const std::string& what);

/// A body of `scene` by name or index.
/// @throws InputError naming `where`, the value and the scene's bodies.
int BodyIndex(const engine::Scene& scene, const pybind11::handle& body, const std::string& where);

/// A gripper of `scene` by name or index.
/// @throws InputError naming the value and the scene's grippers.
int GripperIndex(const engine::Scene& scene, const pybind11::handle& gripper);

/// (w, x, y, z) from Python, normalized, or `otherwise` for None.
/// @throws InputError naming `where`.
Eigen::Quaterniond ToQuaternion(const pybind11::object& quaternion, const std::string& where,
                                const Eigen::Quaterniond& otherwise);

/// A contact's friction as {"mu", "e_t", "e_o", "e_r"}.
pybind11::dict FrictionDict(const engine::Friction& f);

/// A Python value (dict, list, tuple, numpy array, number, bool, str, None) as flow YAML text:
/// numbers to the last bit, strings double-quoted so that they stay strings.
std::string YamlText(const pybind11::handle& value);

/// {"bodies.0.mass": 3} or ["bodies.0.mass=3"] as the CLI's --set strings (a dict's values as
/// YamlText, a list's strings as the CLI's, parsed as YAML).
std::vector<std::string> Overrides(const pybind11::object& overrides);

/// The camera of `camera`: None for the scene's `output` camera (automatic framing unless
/// fixed), or a dict with position and target (m, world) and optionally up and fov (degrees),
/// the scene's fixed camera filling in what is left out.
/// @throws InputError for another type or an unknown key, naming it.
render::CameraSpec CameraOf(const engine::OutputSettings& output, const pybind11::object& camera);

}  // namespace ecpsim::python
