#include "python/conversions.h"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common/errors.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

using Eigen::Vector3d;

// an entry of `items` (each with a `name`) by name or index; `what` ("body") for the message
template <typename Item>
int IndexByName(const std::vector<Item>& items, const py::handle& key, const std::string& where,
                const char* what) {
  if (py::isinstance<py::int_>(key)) {
    const long i = key.cast<long>();
    if (i >= 0 && i < static_cast<long>(items.size())) return static_cast<int>(i);
  } else if (py::isinstance<py::str>(key)) {
    const std::string name = key.cast<std::string>();
    for (size_t i = 0; i < items.size(); ++i) {
      if (items[i].name == name) return static_cast<int>(i);
    }
  }
  std::string names;
  for (const Item& item : items) names += (names.empty() ? "" : ", ") + item.name;
  throw InputError(fmt::format("{}: {} = {}: expected a {} name ({}) or an index below {}", where,
                               what, py::repr(key).cast<std::string>(), what,
                               names.empty() ? "the scene has none" : names, items.size()));
}

// a YAML double-quoted scalar: a string stays a string ("t < 0.3 ? 0.2 : 3" is no mapping)
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

std::string YamlText(const py::handle& value) {
  if (value.is_none()) return "null";
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value) ||
      py::isinstance(value, py::module_::import("numpy").attr("floating"))) {
    const double x = value.cast<double>();
    if (std::isnan(x)) return ".nan";
    if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
    return py::repr(py::float_(x)).cast<std::string>();
  }
  if (py::isinstance<py::str>(value)) return Quoted(value.cast<std::string>());
  if (py::isinstance<py::dict>(value)) {
    std::string text;
    for (const auto& item : value.cast<py::dict>()) {
      text += fmt::format("{}{}: {}", text.empty() ? "" : ", ", YamlText(item.first),
                          YamlText(item.second));
    }
    return "{" + text + "}";
  }
  if (py::hasattr(value, "tolist")) return YamlText(value.attr("tolist")());
  if (py::isinstance<py::sequence>(value)) {
    std::string text;
    for (const auto& item : value.cast<py::sequence>()) {
      text += (text.empty() ? "" : ", ") + YamlText(item);
    }
    return "[" + text + "]";
  }
  return Quoted(py::str(value).cast<std::string>());
}

py::array_t<double> Array(const double* data, std::vector<py::ssize_t> shape) {
  py::array_t<double> a(shape);
  std::memcpy(a.mutable_data(), data, static_cast<size_t>(a.size()) * sizeof(double));
  return a;
}

py::array_t<double> Array(const Vector3d& v) { return Array(v.data(), {3}); }

py::array_t<double> Array(const Eigen::Matrix3d& m) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> rows = m;
  return Array(rows.data(), {3, 3});
}

Vector3d ToVector3(const py::handle& value, const std::string& what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 1 || a.shape(0) != 3) {
    throw InputError(fmt::format("{} = {}: expected 3 numbers [x, y, z]", what,
                                 py::str(value).cast<std::string>()));
  }
  return Vector3d(a.at(0), a.at(1), a.at(2));
}

double ToDouble(const py::handle& value, const std::string& what) {
  try {
    return value.cast<double>();
  } catch (const py::cast_error&) {
    throw InputError(
        fmt::format("{} = {}: expected a number", what, py::repr(value).cast<std::string>()));
  }
}

int BodyIndex(const engine::Scene& scene, const py::handle& body, const std::string& where) {
  return IndexByName(scene.bodies, body, where, "body");
}

int GripperIndex(const engine::Scene& scene, const py::handle& gripper) {
  return IndexByName(scene.grippers, gripper, "set_gripper_target", "gripper");
}

Eigen::Quaterniond ToQuaternion(const py::object& quaternion, const std::string& where,
                                const Eigen::Quaterniond& otherwise) {
  if (quaternion.is_none()) return otherwise;
  const auto q = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(quaternion);
  if (!q || q.ndim() != 1 || q.shape(0) != 4) {
    throw ecpsim::InputError(fmt::format("{}: quaternion = {}: expected 4 numbers (w, x, y, z)",
                                         where, py::str(quaternion).cast<std::string>()));
  }
  return Eigen::Quaterniond(q.at(0), q.at(1), q.at(2), q.at(3));
}

std::vector<std::string> Overrides(const py::object& overrides) {
  std::vector<std::string> result;
  if (overrides.is_none()) return result;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& item : overrides.cast<py::dict>()) {
      result.push_back(py::str(item.first).cast<std::string>() + "=" + YamlText(item.second));
    }
    return result;
  }
  if (py::isinstance<py::str>(overrides)) {
    throw InputError(
        fmt::format("overrides = {}: expected a dict {{\"key\": value}} or a list of "
                    "\"key=value\" strings",
                    py::repr(overrides).cast<std::string>()));
  }
  for (const auto& item : overrides) result.push_back(py::str(item).cast<std::string>());
  return result;
}

py::dict FrictionDict(const engine::Friction& f) {
  py::dict d;
  d["mu"] = f.mu;
  d["e_t"] = f.e_t;
  d["e_o"] = f.e_o;
  if (f.e_r_patch) {
    d["e_r"] = "patch";
  } else {
    d["e_r"] = f.e_r;
  }
  return d;
}

render::CameraSpec CameraOf(const engine::OutputSettings& output, const py::object& camera) {
  render::CameraSpec spec;
  if (camera.is_none()) {
    if (output.camera_fixed) {
      spec.automatic = false;
      spec.position = output.camera_position;
      spec.target = output.camera_target;
      spec.fov_y_deg = output.camera_fov_deg;
    }
    return spec;
  }
  if (!py::isinstance<py::dict>(camera)) {
    throw InputError(
        fmt::format("camera = {}: expected None (the scene's camera) or a dict with "
                    "position, target, and optionally up and fov (degrees)",
                    py::repr(camera).cast<std::string>()));
  }
  spec.automatic = false;
  spec.position = output.camera_position;
  spec.target = output.camera_target;
  spec.fov_y_deg = output.camera_fov_deg;
  for (const auto& item : camera.cast<py::dict>()) {
    const std::string key = py::str(item.first).cast<std::string>();
    if (key == "position") {
      spec.position = ToVector3(item.second, "camera.position");
    } else if (key == "target") {
      spec.target = ToVector3(item.second, "camera.target");
    } else if (key == "up") {
      spec.up = ToVector3(item.second, "camera.up");
    } else if (key == "fov") {
      spec.fov_y_deg = item.second.cast<double>();
    } else {
      throw InputError(
          fmt::format("camera.{}: unknown key; expected position, target, up or fov", key));
    }
  }
  return spec;
}

}  // namespace ecpsim::python
