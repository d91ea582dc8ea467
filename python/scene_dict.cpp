#include "python/scene_dict.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common/errors.h"
#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/scene_limits.h"
#include "geometry/convex_shape.h"
#include "python/conversions.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

using Eigen::Vector3d;

// a dict's keys, each read once; the rest are unknown (named in the error, as the loader does)
class DictReader {
 public:
  DictReader(const py::handle& value, std::string key) : key_(std::move(key)) {
    if (!py::isinstance<py::dict>(value)) {
      throw InputError(
          fmt::format("{} = {}: expected a dict", key_, py::repr(value).cast<std::string>()));
    }
    dict_ = value.cast<py::dict>();
  }
  bool Has(const char* name) const { return dict_.contains(name); }
  py::object Get(const char* name) {
    if (!dict_.contains(name)) {
      throw InputError(fmt::format("{}.{} = (missing): expected a value", key_, name));
    }
    used_.push_back(name);
    return dict_[name];
  }
  std::string Key(const char* name) const { return key_ + "." + name; }
  double Number(const char* name, double fallback) {
    if (!Has(name)) return fallback;
    const py::object value = Get(name);
    try {
      return value.cast<double>();
    } catch (const py::cast_error&) {
      throw InputError(fmt::format("{} = {}: expected a number", Key(name),
                                   py::repr(value).cast<std::string>()));
    }
  }
  Vector3d Vector(const char* name, const Vector3d& fallback) {
    return Has(name) ? ToVector3(Get(name), Key(name)) : fallback;
  }
  // every key was read
  void Finish() const {
    for (const auto& item : dict_) {
      const std::string name = py::str(item.first).cast<std::string>();
      if (std::find(used_.begin(), used_.end(), name) == used_.end()) {
        throw InputError(fmt::format("{}.{}: unknown key", key_, name));
      }
    }
  }

 private:
  std::string key_;
  py::dict dict_;
  std::vector<std::string> used_;
};

engine::Friction ReadFriction(const py::handle& value, const std::string& key,
                              engine::Friction friction) {
  DictReader d(value, key);
  friction.mu = d.Number("mu", friction.mu);
  friction.e_t = d.Number("e_t", friction.e_t);
  friction.e_o = d.Number("e_o", friction.e_o);
  // e_r: a length, or "patch" as in a scene file (docs/scene_format.md)
  if (d.Has("e_r") && py::isinstance<py::str>(d.Get("e_r"))) {
    const std::string e_r = d.Get("e_r").cast<std::string>();
    if (e_r != "patch") {
      throw InputError(fmt::format("{} = '{}': expected a torsional ellipsoid semi-axis > 0 m, "
                                   "or \"patch\"",
                                   d.Key("e_r"), e_r));
    }
    friction.e_r_patch = true;
  } else if (d.Has("e_r")) {
    friction.e_r = d.Number("e_r", friction.e_r);
    friction.e_r_patch = false;
  }
  d.Finish();
  return friction;
}

// checked before the builders, which demand valid sizes and masses (ValidateScene checks the rest)
double Positive(double value, const engine::PositiveRange& range, const std::string& key) {
  const std::string problem = engine::OutOfRange(value, range);
  if (!problem.empty()) throw InputError(fmt::format("{} = {}: expected {}", key, value, problem));
  return value;
}

engine::Body ReadBody(const py::handle& value, const std::string& key,
                      const engine::Friction& ground_friction, py::object& own_friction) {
  DictReader d(value, key);
  const std::string name = d.Get("name").cast<std::string>();
  const double mass = Positive(d.Number("mass", 1), engine::kMassRange, d.Key("mass"));
  engine::Body body;
  if (d.Has("box") == d.Has("mesh")) {
    throw InputError(fmt::format("{}: expected one shape, `box` [x, y, z] m or `mesh` path", key));
  }
  if (d.Has("box")) {
    Vector3d size = d.Vector("box", Vector3d::Zero());
    for (int i = 0; i < 3; ++i) Positive(size[i], engine::kLengthRange, d.Key("box"));
    body = engine::MakeBoxBody(size, mass, name);
  } else {
    const std::string path = d.Get("mesh").cast<std::string>();
    std::optional<double> scale;
    if (d.Has("scale")) scale = d.Number("scale", 1);
    const engine::ScaledMesh mesh =
        engine::LoadScaledMesh(path, scale, std::nullopt, {d.Key("scale"), d.Key("units")});
    body = engine::MakeMeshBody(mesh.mesh, mass, name);
  }
  body.p0 = d.Vector("position", Vector3d::Zero());
  if (d.Has("quaternion")) {
    const auto q =
        py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(d.Get("quaternion"));
    if (!q || q.ndim() != 1 || q.shape(0) != 4) {
      throw InputError(fmt::format("{}: expected 4 numbers (w, x, y, z)", d.Key("quaternion")));
    }
    body.q0 = Eigen::Quaterniond(q.at(0), q.at(1), q.at(2), q.at(3));
  }
  body.v0 = d.Vector("velocity", Vector3d::Zero());
  body.w0 = d.Vector("angular_velocity", Vector3d::Zero());
  if (d.Has("allow_initial_penetration")) {
    body.allow_initial_penetration = d.Get("allow_initial_penetration").cast<bool>();
  }
  body.friction = ground_friction;
  if (d.Has("friction")) {
    own_friction = d.Get("friction");
    body.friction = ReadFriction(own_friction, d.Key("friction"), ground_friction);
  }
  if (d.Has("kinematic")) {
    // a constant twist from the initial pose (the format's `motion: velocity:`)
    DictReader k(d.Get("kinematic"), d.Key("kinematic"));
    engine::ConstantTwist twist;
    twist.start = {body.p0, body.q0};
    twist.v = k.Vector("velocity", Vector3d::Zero());
    twist.w = k.Vector("angular_velocity", Vector3d::Zero());
    k.Finish();
    body.motion = std::make_shared<const engine::KinematicMotion>(twist, d.Key("kinematic"));
  }
  d.Finish();
  return body;
}

engine::Load ReadLoad(const engine::Scene& scene, const py::handle& value, const std::string& key) {
  DictReader d(value, key);
  engine::Load load;
  load.body = BodyIndex(scene, d.Get("body"), d.Key("body"));
  if (d.Has("force") == d.Has("torque")) {
    throw InputError(fmt::format("{}: expected one of `force` and `torque`", key));
  }
  const char* kind = d.Has("force") ? "force" : "torque";
  load.kind = d.Has("force") ? engine::Load::Kind::kForce : engine::Load::Kind::kTorque;
  const py::object components = d.Get(kind);
  const std::string where = d.Key(kind);
  if (!py::isinstance<py::sequence>(components) || py::len(components) != 3) {
    throw InputError(fmt::format("{} = {}: expected 3 numbers or expressions of t", where,
                                 py::repr(components).cast<std::string>()));
  }
  engine::TimeFunction* targets[3] = {&load.x, &load.y, &load.z};
  for (int i = 0; i < 3; ++i) {
    const py::object c = components[py::int_(i)];
    *targets[i] = py::isinstance<py::str>(c)
                      ? engine::TimeFunction(c.cast<std::string>(), fmt::format("{}[{}]", where, i))
                      : engine::TimeFunction(c.cast<double>());
  }
  if (d.Has("at")) {
    load.at_point = true;
    load.point_B = d.Vector("at", Vector3d::Zero());
  }
  load.start = d.Number("start", 0);
  load.end = d.Number("end", load.end);
  d.Finish();
  return load;
}

// the value at `key` (a path such as `bodies[0].friction.mu`) under `root`, or null when the
// arguments do not give it
py::object ValueAt(const py::handle& root, const std::string& key) {
  py::object node = py::reinterpret_borrow<py::object>(root);
  size_t i = 0;
  while (i < key.size()) {
    if (key[i] == '[') {
      const size_t close = key.find(']', i);
      if (close == std::string::npos) return py::object();
      const size_t index = std::stoul(key.substr(i + 1, close - i - 1));
      if (!py::isinstance<py::sequence>(node) || py::isinstance<py::str>(node) ||
          py::len(node) <= index) {
        return py::object();
      }
      node = node[py::int_(index)];
      i = close + 1;
      continue;
    }
    if (key[i] == '.') ++i;
    const size_t end = std::min(key.find('.', i), key.find('[', i));
    const std::string name = key.substr(i, end - i);
    if (!py::isinstance<py::dict>(node) || !node.cast<py::dict>().contains(name)) {
      return py::object();
    }
    node = node[py::str(name)];
    i = std::min(end, key.size());
  }
  return node;
}

// a Scene key in make_scene's terms: the default ground is `friction`, a box is `box`
std::string ArgumentKey(const std::string& scene_key, bool default_ground) {
  std::string key = scene_key;
  const std::string ground = "obstacles[0].";
  if (default_ground && key.rfind(ground, 0) == 0) key = key.substr(ground.size());
  const std::string shape = ".shape";
  if (key.size() > shape.size() && key.compare(key.size() - shape.size(), shape.size(), shape) == 0)
    key.replace(key.size() - shape.size(), shape.size(), ".box");
  return key;
}

// a ValidateScene error at the first of its keys that the arguments give (not a dict: that holds
// the value's keys), else at its first key; the value is the one the scene holds
InputError Locate(const engine::SceneError& error, const py::dict& arguments, bool default_ground) {
  std::string located = ArgumentKey(error.keys().at(0), default_ground);
  for (const std::string& scene_key : error.keys()) {
    const std::string key = ArgumentKey(scene_key, default_ground);
    const py::object value = ValueAt(arguments, key);
    if (value && !py::isinstance<py::dict>(value)) {
      located = key;
      break;
    }
  }
  return InputError(fmt::format("{} = {}: expected {}", located, error.value(), error.expected()));
}

}  // namespace

std::shared_ptr<engine::LoadedScene> MakeScene(const py::list& bodies, const py::object& obstacles,
                                               double h, double duration, const py::handle& gravity,
                                               const py::object& friction, const py::object& loads,
                                               const std::string& model) {
  auto loaded = std::make_shared<engine::LoadedScene>();
  engine::Scene& scene = loaded->scene;
  scene.source = "make_scene";
  scene.h = h;
  scene.duration = duration;
  scene.gravity = ToVector3(gravity, "gravity");
  const engine::Friction ground_friction =
      friction.is_none() ? engine::Friction{}
                         : ReadFriction(friction, "friction", engine::Friction{});
  // obstacles: half-spaces n · x ≤ offset; by default the ground z ≤ 0
  if (obstacles.is_none()) {
    scene.obstacles.push_back(
        {"ground", geometry::MakeHalfSpace(Vector3d::UnitZ(), 0), ground_friction});
  } else {
    int i = 0;
    for (const auto& item : obstacles) {
      const std::string key = fmt::format("obstacles[{}]", i++);
      DictReader d(item, key);
      engine::Obstacle obstacle;
      obstacle.name = d.Get("name").cast<std::string>();
      const Vector3d normal = d.Vector("normal", Vector3d::UnitZ());
      if (!normal.allFinite() || normal.norm() == 0) {
        throw InputError(fmt::format("{} = [{}, {}, {}]: expected a finite, non-zero normal",
                                     d.Key("normal"), normal.x(), normal.y(), normal.z()));
      }
      obstacle.shape = geometry::MakeHalfSpace(normal.normalized(), d.Number("offset", 0));
      obstacle.friction = d.Has("friction")
                              ? ReadFriction(d.Get("friction"), d.Key("friction"), ground_friction)
                              : ground_friction;
      d.Finish();
      scene.obstacles.push_back(obstacle);
    }
  }
  // bodies; each dynamic one touches every obstacle with the obstacle's friction under its own
  std::vector<py::object> own(bodies.size(), py::none());
  for (size_t b = 0; b < bodies.size(); ++b) {
    scene.bodies.push_back(
        ReadBody(bodies[b], fmt::format("bodies[{}]", b),
                 scene.obstacles.empty() ? ground_friction : scene.obstacles[0].friction, own[b]));
  }
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    if (scene.bodies[b].IsKinematic()) continue;
    for (size_t o = 0; o < scene.obstacles.size(); ++o) {
      engine::ContactPair pair{static_cast<int>(b), static_cast<int>(o),
                               scene.obstacles[o].friction};
      if (!own[b].is_none()) {
        pair.friction = ReadFriction(own[b], fmt::format("bodies[{}].friction", b), pair.friction);
      }
      scene.contacts.push_back(pair);
    }
  }
  engine::AddBodyPairs(scene);
  if (!loads.is_none()) {
    int i = 0;
    for (const auto& item : loads)
      scene.loads.push_back(ReadLoad(scene, item, fmt::format("loads[{}]", i++)));
  }
  const std::map<std::string, engine::ContactModel> models = {
      {"auto", engine::ContactModel::kAuto},
      {"hull", engine::ContactModel::kHull},
      {"planar", engine::ContactModel::kPlanar},
      {"multipatch", engine::ContactModel::kMultiPatch},
      {"point", engine::ContactModel::kPoint}};
  if (models.count(model) == 0) {
    throw InputError(
        fmt::format("model = {}: expected auto, hull, planar, multipatch or point", model));
  }
  scene.model = models.at(model);
  // the checks every scene passes, a file's too (engine/scene_io/scene_validation.h)
  try {
    engine::ValidateScene(scene);
  } catch (const engine::SceneError& e) {
    const py::dict arguments(py::arg("bodies") = bodies, py::arg("obstacles") = obstacles,
                             py::arg("h") = h, py::arg("duration") = duration,
                             py::arg("gravity") = gravity, py::arg("friction") = friction,
                             py::arg("loads") = loads);
    throw Locate(e, arguments, obstacles.is_none());
  }
  return loaded;
}

}  // namespace ecpsim::python
