// The `ecpsim` Python module (pybind11): scenes, simulations stepped from Python, trajectories as
// numpy columns, frames as numpy images, convex hulls of meshes. Reference: docs/python.md. This
// file holds the bindings; the stateful part is python/simulation.h, and conversions, state
// arrays are python/conversions.h and state_arrays.h.

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "common/errors.h"
#include "engine/report/trajectory_columns.h"
#include "engine/scene_io/mesh_report.h"
#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/scene_limits.h"
#include "engine/time_step.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_topology.h"
#include "python/conversions.h"
#include "python/jacobian_bindings.h"
#include "python/media_bindings.h"
#include "python/py_simulation.h"
#include "python/rollout_bindings.h"
#include "python/simulation.h"
#include "python/state_arrays.h"
#include "python/state_pickle.h"
#include "python/step_interrupt.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

using Eigen::Vector3d;

// ---- scenes -------------------------------------------------------------------------------

py::dict BodyDict(const engine::Body& body) {
  py::dict d;
  d["name"] = body.name;
  d["kinematic"] = body.IsKinematic();
  d["mass"] = body.mass;
  d["inertia"] = Array(body.inertia);
  d["position"] = Array(body.p0);
  const Eigen::Quaterniond& q = body.q0;
  const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  d["quaternion"] = Array(wxyz, {4});
  d["velocity"] = Array(body.v0);
  d["angular_velocity"] = Array(body.w0);
  d["friction"] = FrictionDict(body.friction);
  d["mesh_vertices"] = body.mesh.vertices.size();
  return d;
}

// ---- the Python Simulation ----------------------------------------------------------------

py::array_t<std::uint8_t> Render(PySimulation& self, int width, int height,
                                 const py::object& camera, bool overlays) {
  for (const int pixels : {width, height}) {
    if (pixels < engine::kMinFramePixels || pixels > engine::kMaxFramePixels) {
      throw InputError(fmt::format("render: width × height = {} × {}: expected {} … {} pixels each",
                                   width, height, engine::kMinFramePixels,
                                   engine::kMaxFramePixels));
    }
  }
  const render::CameraSpec spec = CameraOf(self.scene->output, camera);
  render::Image image;
  {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(self.mutex);
    RenderCache& cache = self.render;
    if (!cache.renderer || cache.width != width || cache.height != height ||
        cache.thread != std::this_thread::get_id()) {
      cache.renderer.reset();
      render::RenderSettings settings;
      settings.width = width;
      settings.height = height;
      cache.renderer = std::make_unique<render::Renderer>(settings);
      cache.width = width, cache.height = height;
      cache.thread = std::this_thread::get_id();
    }
    if (!cache.frames) {
      cache.frames = std::make_unique<render::SceneFrameBuilder>(self.sim.scene());
    }
    render::FrameInput frame = cache.frames->Build(
        self.sim.state(), self.sim.last_report().iterations, self.sim.last_report().models);
    frame.camera = spec;
    frame.show.hull = frame.show.inset = frame.show.text = frame.show.force_arrow = overlays;
    image = cache.renderer->Render(frame);
  }
  py::array_t<std::uint8_t> out({image.height, image.width, 3});
  std::memcpy(out.mutable_data(), image.pixels.data(), image.pixels.size());
  return out;
}

// ---- run and hull -------------------------------------------------------------------------

py::dict Run(const engine::Scene& scene, const py::object& duration_arg, long every) {
  if (every < 1) {
    throw InputError(fmt::format("run: every = {}: expected an integer ≥ 1", every));
  }
  const double duration = duration_arg.is_none() ? scene.duration : duration_arg.cast<double>();
  const std::string problem = std::isfinite(duration) && duration > 0
                                  ? engine::StepCountProblem(duration, scene.h)
                                  : std::string("a finite duration > 0 s");
  if (!problem.empty()) {
    throw InputError(fmt::format("{}: duration = {}, h = {}: expected {}", scene.source, duration,
                                 scene.h, problem));
  }
  const long steps = engine::PlannedSteps(duration, scene.h);
  const std::vector<std::string> columns = engine::TrajectoryColumns(scene);
  const std::vector<std::string> model_columns = engine::TrajectoryModelColumns(scene);
  std::vector<double> rows;
  std::vector<std::string> models;
  {
    py::gil_scoped_release release;
    engine::State state = engine::InitialState(scene);
    engine::StepWorkspace workspace;
    engine::StepReport report;
    report.converged = true;
    auto add_row = [&] {
      const std::vector<double> row = engine::TrajectoryValues(scene, state, report);
      // never a NaN in an output (as trajectory.csv's writer)
      for (size_t i = 0; i < row.size(); ++i) {
        if (!std::isfinite(row[i])) {
          throw engine::SolverFailure(
              fmt::format("t = {} s: {} = {} is not finite", state.t, columns[i], row[i]));
        }
      }
      rows.insert(rows.end(), row.begin(), row.end());
      const std::vector<std::string> row_models = engine::TrajectoryModels(scene, report);
      models.insert(models.end(), row_models.begin(), row_models.end());
    };
    add_row();
    for (long k = 1; k <= steps; ++k) {
      report = engine::Step(scene, state, workspace);
      if (k % every == 0 || k == steps) add_row();
    }
  }
  const size_t n = rows.size() / columns.size();
  py::dict result;
  for (size_t c = 0; c < columns.size(); ++c) {
    py::array_t<double> column(static_cast<py::ssize_t>(n));
    double* out = column.mutable_data();
    for (size_t r = 0; r < n; ++r) out[r] = rows[r * columns.size() + c];
    result[py::str(columns[c])] = column;
  }
  // the model columns as numpy arrays of str, as the CSV's text columns
  for (size_t c = 0; c < model_columns.size(); ++c) {
    py::list column;
    for (size_t r = 0; r < n; ++r) column.append(models[r * model_columns.size() + c]);
    result[py::str(model_columns[c])] = py::module_::import("numpy").attr("array")(column);
  }
  return result;
}

py::dict Hull(const std::string& path, const std::optional<double>& scale,
              const std::optional<std::string>& units, const std::optional<double>& mass,
              const std::optional<double>& density) {
  if (mass && density) {
    throw InputError(fmt::format("hull({}): mass = {} and density = {}: expected one of them", path,
                                 *mass, *density));
  }
  for (const auto& [value, range, key] : {std::tuple{mass, engine::kMassRange, "mass"},
                                          std::tuple{density, engine::kDensityRange, "density"}}) {
    if (value && !engine::OutOfRange(*value, range).empty()) {
      throw InputError(fmt::format("hull({}): {} = {}: expected {}", path, key, *value,
                                   engine::OutOfRange(*value, range)));
    }
  }
  py::gil_scoped_release release;
  engine::ScaledMesh scaled = engine::LoadScaledMesh(path, scale, units, {"scale", "units"});
  std::vector<std::string> warnings;
  if (!scaled.warning.empty()) warnings.push_back(scaled.warning);
  // as `ecpsim hull`: the mesh's own mass properties when it bounds a solid, else its hull's
  const engine::MeshReport report = engine::ReportMesh(std::move(scaled), path, mass, density);
  if (!report.warning.empty()) warnings.push_back(report.warning);
  const geometry::ConvexHull& body_hull = report.body_hull;
  const geometry::MassProperties& props = report.props;

  py::gil_scoped_acquire acquire;
  const py::ssize_t m = static_cast<py::ssize_t>(body_hull.normals.size());
  py::array_t<double> A({m, py::ssize_t{3}}), b(m);
  for (py::ssize_t i = 0; i < m; ++i) {
    for (int k = 0; k < 3; ++k) A.mutable_at(i, k) = body_hull.normals[i][k];
    b.mutable_at(i) = body_hull.offsets[i];
  }
  py::array_t<double> vertices(
      {static_cast<py::ssize_t>(body_hull.vertices.size()), py::ssize_t{3}});
  for (size_t i = 0; i < body_hull.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices.mutable_at(i, k) = body_hull.vertices[i][k];
  }
  py::dict d;
  d["A"] = A;
  d["b"] = b;
  d["vertices"] = vertices;
  d["faces"] = body_hull.faces;
  d["volume"] = props.volume;
  d["mass"] = props.mass;
  d["density"] = props.mass / props.volume;
  d["center_of_mass"] = Array(props.center_of_mass);
  d["inertia"] = Array(props.inertia);
  d["principal_moments"] = Array(props.principal_moments);
  d["principal_axes"] = Array(props.principal_axes);
  d["scale"] = report.scaled.scale;
  d["closed"] = report.topology.closed;
  d["oriented"] = report.topology.consistently_oriented;
  d["mass_source"] = report.mass_source;
  d["warnings"] = warnings;
  return d;
}

// ecpsim.SceneWarning, made when the module loads
PyObject* scene_warning = nullptr;

// each of the scene's warnings as a SceneWarning, so that Python's filters see it (and an
// "error" filter raises it)
void WarnOf(const engine::LoadedScene& loaded) {
  for (const std::string& warning : loaded.warnings) {
    if (PyErr_WarnEx(scene_warning, warning.c_str(), 2) != 0) throw py::error_already_set();
  }
}

// the mesh reader helper installed beside the module (cmake --install) when none is chosen
void FindMeshReader() {
  if (const char* chosen = std::getenv("ECPSIM_MESH_READER"); chosen != nullptr && *chosen) return;
  Dl_info info;
  if (dladdr(reinterpret_cast<void*>(&FindMeshReader), &info) == 0 || !info.dli_fname) return;
  std::string beside(info.dli_fname);
  beside = beside.substr(0, beside.rfind('/') + 1) + "ecpsim-mesh-reader";
  if (::access(beside.c_str(), X_OK) == 0) ::setenv("ECPSIM_MESH_READER", beside.c_str(), 0);
}

}  // namespace
}  // namespace ecpsim::python

PYBIND11_MODULE(ecpsim, m) {
  using namespace ecpsim::python;
  namespace engine = ecpsim::engine;
  FindMeshReader();
  RecordMainThread();
  m.doc() =
      "ecpsim: rigid bodies with planar non-convex contact (Xie & Chakraborty), stepped from "
      "Python. Quaternions are (w, x, y, z), everything else SI in the world frame. Reference: "
      "docs/python.md.";
  // project(VERSION) of CMakeLists.txt, where the version is written once (python/CMakeLists.txt)
  m.attr("__version__") = ECPSIM_VERSION;

  // errors: the CLI's messages; InputError (exit code 1) is a ValueError
  py::register_exception<ecpsim::InputError>(m, "InputError", PyExc_ValueError).doc() =
      "Bad input: a scene file, an override, a mesh, an argument. The message names the file:line, "
      "key, value and what was expected, as the CLI's (exit code 1).";
  scene_warning = PyErr_NewExceptionWithDoc(
      "ecpsim.SceneWarning",
      "A scene loaded, with a note that is no error (a mesh of implausible size: wrong units?).",
      PyExc_UserWarning, nullptr);
  if (scene_warning == nullptr) throw py::error_already_set();
  m.attr("SceneWarning") = py::handle(scene_warning);
  py::register_exception<engine::SolverFailure>(m, "SolverFailure", PyExc_RuntimeError).doc() =
      "A step could not be solved after every retry; the message names time, body, residual and "
      "what was tried (the CLI's exit code 3). The simulation keeps the last good state.";
  py::register_exception<engine::ModelInvalid>(m, "ModelInvalid", PyExc_RuntimeError).doc() =
      "The scene's contact model does not apply (e.g. the planar model and a tipping body); the "
      "CLI's exit code 5.";

  py::class_<engine::LoadedScene, SceneHandle>(
      m, "Scene",
      "An immutable, validated scene (bodies, obstacles, contacts, loads, settings). Make one with "
      "load_scene(); a Simulation steps it.")
      .def_property_readonly(
          "source", [](const engine::LoadedScene& loaded) { return loaded.scene.source; },
          "The file the scene was read from.")
      .def_property_readonly(
          "h", [](const engine::LoadedScene& loaded) { return loaded.scene.h; }, "Time step, s.")
      .def_property_readonly(
          "duration", [](const engine::LoadedScene& loaded) { return loaded.scene.duration; },
          "Duration of run(), s.")
      .def_property_readonly(
          "gravity", [](const engine::LoadedScene& loaded) { return Array(loaded.scene.gravity); },
          "Gravity (3,), m/s², world frame.")
      .def_property_readonly(
          "model",
          [](const engine::LoadedScene& loaded) {
            return engine::ContactModelName(loaded.scene.model);
          },
          "The contact model: auto, hull, planar, multipatch or point.")
      .def_property_readonly(
          "body_names",
          [](const engine::LoadedScene& loaded) {
            const engine::Scene& s = loaded.scene;
            std::vector<std::string> names;
            for (const engine::Body& b : s.bodies) names.push_back(b.name);
            return names;
          },
          "Names of the bodies, in the order of every per-body array.")
      .def_property_readonly(
          "bodies",
          [](const engine::LoadedScene& loaded) {
            const engine::Scene& s = loaded.scene;
            py::list list;
            for (const engine::Body& b : s.bodies) list.append(BodyDict(b));
            return list;
          },
          "Per body a dict: name, kinematic, mass (kg), inertia (3, 3) kg·m² about the CM, the "
          "initial position, quaternion (w, x, y, z), velocity, angular_velocity, friction.")
      .def_property_readonly(
          "obstacles",
          [](const engine::LoadedScene& loaded) {
            const engine::Scene& s = loaded.scene;
            py::list list;
            for (const engine::Obstacle& o : s.obstacles) {
              py::dict d;
              d["name"] = o.name;
              d["friction"] = FrictionDict(o.friction);
              list.append(d);
            }
            return list;
          },
          "Per fixed obstacle a dict: name, friction.")
      .def_property_readonly(
          "grippers",
          [](const engine::LoadedScene& loaded) {
            const engine::Scene& s = loaded.scene;
            py::list list;
            for (const engine::Gripper& g : s.grippers) {
              py::dict d;
              d["name"] = g.name;
              d["jaws"] = py::make_tuple(s.bodies[g.jaws[0]].name, s.bodies[g.jaws[1]].name);
              d["axis"] = Array(g.axis);
              d["force"] = g.force.expression().empty() ? py::cast(g.force(0))
                                                        : py::cast(g.force.expression());
              list.append(d);
            }
            return list;
          },
          "Per gripper a dict: name, jaws (the two body names, the first closing along +axis), "
          "axis (its frame's coordinates), force (N: a number, or the scene's expression of t).")
      .def_property_readonly(
          "contact_names",
          [](const engine::LoadedScene& loaded) {
            const engine::Scene& s = loaded.scene;
            std::vector<std::string> names;
            for (const engine::ContactPair& pair : s.contacts)
              names.push_back(ContactName(s, pair));
            return names;
          },
          "Names 'body.other' of the potential contacts, in the order of Simulation.contacts().")
      .def_property_readonly(
          "warnings", [](const engine::LoadedScene& loaded) { return loaded.warnings; },
          "Notes from loading that are no errors (a mesh of implausible size).")
      .def("__repr__", [](const engine::LoadedScene& loaded) {
        const engine::Scene& s = loaded.scene;
        return fmt::format("<ecpsim.Scene '{}': {} bodies, {} obstacles, h = {} s, model {}>",
                           s.source, s.bodies.size(), s.obstacles.size(), s.h,
                           engine::ContactModelName(s.model));
      });

  m.def(
      "load_scene",
      [](const std::filesystem::path& path, const py::object& overrides) {
        const std::vector<std::string> strings = Overrides(overrides);
        SceneHandle loaded;
        {
          py::gil_scoped_release release;
          loaded = std::make_shared<engine::LoadedScene>(engine::LoadScene(path.string(), strings));
        }
        WarnOf(*loaded);
        return loaded;
      },
      py::arg("path"), py::arg("overrides") = py::none(),
      "Reads a YAML scene (docs/scene_format.md) and validates it.\n\n"
      "overrides: the CLI's --set, as a dict {'bodies.0.mass': 3, 'h': 0.005} (values as "
      "Python numbers, bools, strings, lists or dicts; a string stays a string, e.g. "
      "{'grippers.0.force': 't < 0.3 ? 0.2 : 3'}) or a list of 'key=value' strings, parsed as "
      "YAML as the CLI's.\n"
      "Raises InputError with the CLI's file:line:col message; each of Scene.warnings (a mesh "
      "of implausible size: wrong units?) is also warned as SceneWarning.");

  py::class_<engine::State>(
      m, "State",
      "A saved simulation state (Simulation.get_state()): time, poses, velocities and the "
      "contacts' solutions and warm starts. Simulation.set_state() continues from it bit for bit, "
      "also after copy.copy() or a pickle round trip (to another process or machine).")
      .def_property_readonly(
          "time", [](const engine::State& s) { return s.t; }, "s")
      .def_property_readonly(
          "steps", [](const engine::State& s) { return s.steps; }, "Steps taken since t = 0.")
      .def_property_readonly(
          "positions", [](const engine::State& s) { return BodyArray(s, BodyField::kPosition); },
          "(n, 3) centres of mass, m.")
      .def_property_readonly(
          "quaternions",
          [](const engine::State& s) { return BodyArray(s, BodyField::kQuaternion); },
          "(n, 4) orientations body → world, (w, x, y, z).")
      .def_property_readonly(
          "velocities", [](const engine::State& s) { return BodyArray(s, BodyField::kVelocity); },
          "(n, 3) m/s.")
      .def_property_readonly(
          "angular_velocities",
          [](const engine::State& s) { return BodyArray(s, BodyField::kAngularVelocity); },
          "(n, 3) rad/s, world frame.")
      .def("__copy__", [](const engine::State& s) { return engine::State(s); })
      .def(
          "__deepcopy__", [](const engine::State& s, py::dict) { return engine::State(s); },
          py::arg("memo"))
      // pickle (multiprocessing, Dask): plain Python values, the doubles bit for bit
      .def(py::pickle(&StateToTuple, &StateFromTuple));

  py::class_<PySimulation> sim(
      m, "Simulation",
      "One simulation of a Scene, stepped from Python (MuJoCo's MjData with mj_step). Per-body "
      "arrays follow body_names; quaternions are (w, x, y, z) as in trajectory.csv. step() and "
      "render() release the GIL: separate Simulations run in parallel threads.");
  sim.def(py::init([](SceneHandle scene, int threads) {
            auto made = std::make_unique<PySimulation>(std::move(scene));
            made->sim.SetThreads(threads);
            return made;
          }),
          py::arg("scene"), py::kw_only(), py::arg("threads") = 1,
          "Starts at the scene's initial state. `threads`: how many threads solve a step's "
          "contact islands side by side; the result is the same, bit for bit, for any number.")
      .def_property(
          "threads",
          [](PySimulation& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return self.sim.threads();
          },
          [](PySimulation& self, int threads) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            self.sim.SetThreads(threads);
          },
          "Threads that solve a step's contact islands (the result is the same for any number).")
      .def(
          "step",
          [](PySimulation& self, std::int64_t n) {
            if (n < 1) throw ecpsim::InputError(fmt::format("step: n = {}: expected n ≥ 1", n));
            StepInterruptibly(self, n);
          },
          py::arg("n") = 1,
          "Takes n steps of scene.h; wrenches from apply_wrench act on the first. last_report "
          "holds the last step's {converged, iterations, residual, retries, substeps}.\n"
          "Raises SolverFailure or ModelInvalid (the state stays the last good one), InputError "
          "(a load expression not finite). Ctrl-C stops the step in progress within a solver "
          "iteration and raises KeyboardInterrupt, the state the one after the steps done.")
      .def(
          "reset",
          [](PySimulation& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            self.sim.Reset();
          },
          "Back to the initial state; pending wrenches and kinematic targets dropped.")
      .def_property_readonly(
          "scene", [](const PySimulation& self) { return self.scene; }, "The Scene given.")
      .def_property_readonly(
          "time",
          [](PySimulation& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return self.sim.state().t;
          },
          "Simulated time, s (steps · h).")
      .def_property_readonly(
          "steps",
          [](PySimulation& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return self.sim.state().steps;
          },
          "Steps taken since t = 0.")
      .def_property_readonly(
          "body_names",
          [](const PySimulation& self) {
            std::vector<std::string> names;
            for (const engine::Body& b : self.scene->scene.bodies) names.push_back(b.name);
            return names;
          },
          "Names of the bodies, the rows of every per-body array.")
      .def_property_readonly(
          "last_report",
          [](PySimulation& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            py::dict report = ReportDict(self.sim.scene(), self.sim.last_report());
            const std::string& failure = self.sim.last_failure();
            report["failure"] = failure.empty() ? py::object(py::none()) : py::str(failure);
            return report;
          },
          "The last step's {converged, iterations, residual, retries, substeps, models, "
          "failure}: models maps each body's name to what solved its step (free, planar, hull, "
          "multipatch, point, kinematic); of a step that raised SolverFailure or ModelInvalid, "
          "converged is False, residual and retries are the failure's and failure its message "
          "(None after a step that succeeded).")
      .def(
          "get_state",
          [](PySimulation& self) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            return engine::State(self.sim.state());
          },
          "A copy of the full state (a State) for set_state().")
      .def(
          "set_state",
          [](PySimulation& self, const engine::State& state) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            self.sim.SetState(state);
          },
          py::arg("state"),
          "Restores a State from get_state() of a Simulation of the same scene; stepping on is "
          "bit-identical to stepping on from where it was saved (given the same inputs).")
      .def(
          "apply_wrench",
          [](PySimulation& self, const py::handle& body, const py::handle& force,
             const py::handle& torque, const py::object& at) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            const int b = BodyIndex(self.sim.scene(), body, "apply_wrench");
            const std::optional<Vector3d> at_W =
                at.is_none() ? std::nullopt
                             : std::optional<Vector3d>(ToVector3(at, "apply_wrench: at"));
            self.sim.ApplyWrench(b, ToVector3(force, "apply_wrench: force"),
                                 ToVector3(torque, "apply_wrench: torque"), at_W);
          },
          py::arg("body"), py::arg("force") = py::make_tuple(0, 0, 0),
          py::arg("torque") = py::make_tuple(0, 0, 0), py::arg("at") = py::none(),
          "Applies force (N, world) at the world point `at` (default: the CM) and torque (N·m, "
          "world) to a dynamic body (name or index) during the next step only: an applied impulse "
          "h·force, h·torque in that step's MNCP, exactly as a scene load. Calls before one step "
          "add up.")
      .def(
          "set_kinematic_target",
          [](PySimulation& self, const py::handle& body, const py::handle& position,
             const py::object& quaternion) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            const int b = BodyIndex(self.sim.scene(), body, "set_kinematic_target");
            engine::KinematicPose pose;
            pose.p = ToVector3(position, "set_kinematic_target: position");
            pose.q =
                ToQuaternion(quaternion, "set_kinematic_target", self.sim.state().bodies[b].Q_WB);
            self.sim.SetKinematicTarget(b, pose);
          },
          py::arg("body"), py::arg("position"), py::arg("quaternion") = py::none(),
          "Moves a kinematic body (name or index) to `position` (m) and `quaternion` (w, x, y, z; "
          "default: its orientation now) at the end of the next step, at a constant twist; it "
          "stays there until the next target (MuJoCo's mocap bodies).")
      .def(
          "set_gripper_target",
          [](PySimulation& self, const py::handle& gripper, const py::handle& position,
             const py::object& quaternion, const py::object& force) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            const engine::Scene& scene = self.sim.scene();
            const int g = GripperIndex(scene, gripper);
            const double now = static_cast<double>(self.sim.state().steps) * scene.h;
            engine::KinematicPose pose;
            pose.p = ToVector3(position, "set_gripper_target: position");
            pose.q = ToQuaternion(quaternion, "set_gripper_target",
                                  scene.grippers[g].motion->PoseAt(now).q);
            std::optional<double> closing;
            if (!force.is_none()) closing = ToDouble(force, "set_gripper_target: force");
            self.sim.SetGripperTarget(g, pose, closing);
          },
          py::arg("gripper"), py::arg("position"), py::arg("quaternion") = py::none(),
          py::arg("force") = py::none(),
          "Moves a gripper's frame (name or index) to `position` (m) and `quaternion` (w, x, y, "
          "z; default: its orientation now) at the end of the next step, at a constant twist, "
          "and sets its closing force (N on each jaw, ≥ 0; default: unchanged) from the next "
          "step on; both hold until the next target.")
      .def(
          "contacts",
          [](PySimulation& self, bool as_arrays) -> py::object {
            const std::lock_guard<std::mutex> lock(self.mutex);
            if (as_arrays) {
              return ContactArrays(self.sim.scene(), self.sim.state(), self.sim.last_report());
            }
            return ContactList(self.sim.scene(), self.sim.state(), self.sim.last_report());
          },
          py::arg("as_arrays") = false,
          "The contacts' solutions of the last step, one dict per potential contact: name, body, "
          "other (obstacle or body), other_is_body, a1 and a2 (the ECPs, m), normal, tangent, "
          "tangent2, the impulses p_n p_t p_o (N·s) p_r (N·m·s), sigma (m/s), the average forces "
          "f_n f_t f_o (N) f_r (N·m) and force (3,) on the body, mode (separated, sticking or "
          "sliding), model, friction.\n"
          "as_arrays=True: one dict of the same keys (but friction), each a numpy array with a "
          "row per contact ((k,) or (k, 3)), or a list for name, body, other, mode and model.")
      .def(
          "sensor",
          [](PySimulation& self, const py::handle& body) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            const engine::Scene& scene = self.sim.scene();
            const int b = BodyIndex(scene, body, "sensor");
            if (!scene.bodies[static_cast<size_t>(b)].IsKinematic()) {
              throw ecpsim::InputError(fmt::format(
                  "sensor: body '{}' is dynamic: expected a kinematic body (a finger, a jaw), "
                  "whose sensor reads what it pushes",
                  scene.bodies[static_cast<size_t>(b)].name));
            }
            return SensorArray(scene, self.sim.state(), b);
          },
          py::arg("body"),
          "What a force/torque sensor on a kinematic body (name or index) read over the last "
          "step: a (6,) array, the force (N) and moment (N·m, about its reference point) that the "
          "bodies it touches exert on it, world axes — trajectory.csv's <K>.fx … <K>.mz. Zero "
          "before the first step.")
      .def("render", &Render, py::arg("width") = 640, py::arg("height") = 480,
           py::arg("camera") = py::none(), py::arg("overlays") = true,
           "The current state as a uint8 image (height, width, 3), top row first. camera: None "
           "(the scene's: automatic framing unless fixed) or a dict with position, target, and "
           "optionally up and fov (degrees). overlays: hulls, contact forces, inset and text.");

  BindMedia(m, sim);

  // per-body arrays: read as fresh numpy copies, written whole (dynamic bodies)
  for (const BodyField field : {BodyField::kPosition, BodyField::kQuaternion, BodyField::kVelocity,
                                BodyField::kAngularVelocity}) {
    sim.def_property(
        FieldName(field),
        [field](PySimulation& self) {
          const std::lock_guard<std::mutex> lock(self.mutex);
          return BodyArray(self.sim.state(), field);
        },
        [field](PySimulation& self, const py::handle& value) {
          const std::lock_guard<std::mutex> lock(self.mutex);
          SetBodyArray(self.sim.scene(), self.sim.mutable_state(), field, value);
        },
        field == BodyField::kQuaternion
            ? "(n, 4) orientations body → world as (w, x, y, z); settable (normalized)."
            : "(n, 3) per body (m, m/s or rad/s, world frame); settable for dynamic bodies.");
  }

  BindRollout(m, sim);
  BindJacobians(sim);

  m.def(
      "make_scene",
      [](const py::dict& tree, const py::object& overrides, const std::filesystem::path& base_dir) {
        const std::string text = YamlText(tree);
        const std::vector<std::string> strings = Overrides(overrides);
        SceneHandle loaded;
        {
          py::gil_scoped_release release;
          loaded = std::make_shared<engine::LoadedScene>(
              engine::LoadSceneText(text, "make_scene", base_dir.string(), strings));
        }
        WarnOf(*loaded);
        return loaded;
      },
      py::arg("tree"), py::arg("overrides") = py::none(), py::arg("base_dir") = ".",
      "A scene from a dict that is the YAML format's tree (docs/scene_format.md: the same keys, "
      "defaults, ranges and checks as a file's, read by the same loader), e.g. {'duration': 1, "
      "'ground': {'friction': {'mu': 0.3}}, 'bodies': [{'name': 'box', 'shape': {'box': {'size': "
      "[0.1, 0.1, 0.1]}}, 'mass': 1, 'position': [0, 0, 0.05]}]}. Values may be Python or numpy "
      "numbers and arrays; strings stay strings. overrides: as load_scene's. base_dir: the "
      "folder mesh paths are relative to (default: the working directory).\n"
      "Raises InputError naming the key path (make_scene: bodies[0].mass = -1: expected ...); "
      "warns SceneWarning as load_scene.");

  m.def(
      "run",
      [](const SceneHandle& scene, const py::object& duration, const py::object& every) {
        return Run(scene->scene, duration,
                   every.is_none() ? scene->output.every : every.cast<long>());
      },
      py::arg("scene"), py::arg("duration") = py::none(), py::arg("every") = py::none(),
      "Steps the scene from its initial state for `duration` s (default: the scene's) and returns "
      "the trajectory as a dict of numpy columns named as trajectory.csv's (t, px … wz per body, "
      "the contacts' a1x … fr, the sensors', iters, residual): the initial state, every `every`-th "
      "step (default: the scene's output.every) and the last.\n"
      "Raises SolverFailure, ModelInvalid, InputError as the CLI.");

  m.def(
      "hull",
      [](const std::filesystem::path& path, const std::optional<double>& scale,
         const std::optional<std::string>& units, const std::optional<double>& mass,
         const std::optional<double>& density) {
        return Hull(path.string(), scale, units, mass, density);
      },
      py::arg("mesh_path"), py::arg("scale") = py::none(), py::arg("units") = py::none(),
      py::arg("mass") = py::none(), py::arg("density") = py::none(),
      "Mass properties and convex hull of a mesh file (as `ecpsim hull`): a dict with A (m, 3) "
      "and b (m,) of the hull A y ≤ b in the body frame (origin at the centre of mass, mesh axes), "
      "vertices (k, 3), faces, volume (m³), mass (kg), density, center_of_mass (mesh frame), "
      "inertia (3, 3) about the CM, principal_moments, principal_axes (columns), scale, closed, "
      "oriented, mass_source, warnings. scale or units (mm, cm, m, in) convert the mesh to m; "
      "mass or density (default 1000 kg/m³).");
}
