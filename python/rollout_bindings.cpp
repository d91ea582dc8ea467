#include "python/rollout_bindings.h"

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "common/errors.h"
#include "engine/step_report.h"
#include "python/conversions.h"
#include "python/rollout.h"
#include "python/state_arrays.h"
#include "python/step_interrupt.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

// ---- domain randomization -----------------------------------------------------------------

// an inertia as the scene format's `inertia`: 3 principal moments (a diagonal in body axes) or
// a 3 × 3 matrix
Eigen::Matrix3d ToInertia(const py::handle& value, const std::string& where) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (a && a.ndim() == 1 && a.shape(0) == 3) {
    return Eigen::Vector3d(a.at(0), a.at(1), a.at(2)).asDiagonal();
  }
  if (a && a.ndim() == 2 && a.shape(0) == 3 && a.shape(1) == 3) {
    Eigen::Matrix3d inertia;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) inertia(i, j) = a.at(i, j);
    }
    return inertia;
  }
  throw InputError(fmt::format(
      "{}: inertia = {}: expected 3 principal moments [Ixx, Iyy, Izz] or a 3 × 3 matrix "
      "(kg·m², about the CM in body axes)",
      where, py::repr(value).cast<std::string>()));
}

// a contact by its name in Scene.contact_names ('box.ground') or its index
int ContactIndex(const engine::Scene& scene, const py::handle& contact) {
  const size_t n = scene.contacts.size();
  if (py::isinstance<py::int_>(contact)) {
    const long k = contact.cast<long>();
    if (k >= 0 && static_cast<size_t>(k) < n) return static_cast<int>(k);
  } else if (py::isinstance<py::str>(contact)) {
    const std::string name = contact.cast<std::string>();
    for (size_t k = 0; k < n; ++k) {
      if (ContactName(scene, scene.contacts[k]) == name) return static_cast<int>(k);
    }
  }
  std::string names;
  for (const engine::ContactPair& pair : scene.contacts) {
    names += (names.empty() ? "" : ", ") + ContactName(scene, pair);
  }
  throw InputError(fmt::format(
      "set_friction: contact = {}: expected a contact name of Scene.contact_names ({}) or an "
      "index below {}",
      py::repr(contact).cast<std::string>(), names.empty() ? "the scene has none" : names, n));
}

std::optional<double> OptionalDouble(const py::object& value, const std::string& what) {
  if (value.is_none()) return std::nullopt;
  return ToDouble(value, what);
}

// ---- rollout ------------------------------------------------------------------------------

// the arrays a rollout fills, allocated with the GIL held and written without it
struct RolloutArrays {
  py::array_t<double> positions, quaternions, velocities, angular_velocities, time;
  py::array_t<bool> converged;

  RolloutArrays(py::ssize_t sims, py::ssize_t steps, py::ssize_t bodies)
      : positions({sims, steps, bodies, py::ssize_t{3}}),
        quaternions({sims, steps, bodies, py::ssize_t{4}}),
        velocities({sims, steps, bodies, py::ssize_t{3}}),
        angular_velocities({sims, steps, bodies, py::ssize_t{3}}),
        time({sims, steps}),
        converged({sims, steps}) {}

  // simulation i's rows
  RolloutRows Rows(size_t i, size_t steps, size_t bodies) {
    const size_t rows = i * steps;
    return {positions.mutable_data() + rows * bodies * 3,
            quaternions.mutable_data() + rows * bodies * 4,
            velocities.mutable_data() + rows * bodies * 3,
            angular_velocities.mutable_data() + rows * bodies * 3,
            time.mutable_data() + rows,
            converged.mutable_data() + rows};
  }

  py::dict Dict() const {
    py::dict d;
    d["positions"] = positions;
    d["quaternions"] = quaternions;
    d["velocities"] = velocities;
    d["angular_velocities"] = angular_velocities;
    d["time"] = time;
    d["converged"] = converged;
    return d;
  }
};

// the module's exception class for a failure: SolverFailure, ModelInvalid or InputError; none
// for another error (a bug's std::logic_error, memory), which pybind11 translates as it is
py::object ErrorClass(const std::exception_ptr& error) {
  const py::module_ ecpsim = py::module_::import("ecpsim");
  try {
    std::rethrow_exception(error);
  } catch (const engine::SolverFailure&) {
    return ecpsim.attr("SolverFailure");
  } catch (const engine::ModelInvalid&) {
    return ecpsim.attr("ModelInvalid");
  } catch (const InputError&) {
    return ecpsim.attr("InputError");
  } catch (...) {
    return py::none();
  }
}

// raises the first failure's class with a message naming every failure, and as attributes:
// simulation and steps_done (the first's), failures [(simulation, steps_done, message)], and
// results: the completed simulations' arrays (rows of the `completed` indices, as rollout's)
[[noreturn]] void RaiseFailures(const std::vector<RolloutFailure>& failures,
                                const RolloutArrays& arrays, size_t sims, std::int64_t steps) {
  const RolloutFailure& first = failures.front();
  py::object error_class = ErrorClass(first.error);
  if (error_class.is_none()) std::rethrow_exception(first.error);

  std::string message = fmt::format(
      "rollout: simulation {} failed in its step {} of {} (it keeps its state after {} good "
      "steps, t = {} s): {}",
      first.simulation, first.steps_done + 1, steps, first.steps_done, first.t, first.message);
  if (failures.size() > 1) {
    std::string others;
    for (size_t f = 1; f < failures.size(); ++f) {
      others += fmt::format("{}{} (step {})", others.empty() ? "" : ", ", failures[f].simulation,
                            failures[f].steps_done + 1);
    }
    message += fmt::format("; simulations {} failed too (the exception's `failures`)", others);
  }
  message += fmt::format("; the other {} of {} took all {} steps (the exception's `results`)",
                         sims - failures.size(), sims, steps);

  py::list listed;
  std::vector<bool> stopped(sims, false);
  for (const RolloutFailure& f : failures) {
    listed.append(py::make_tuple(f.simulation, f.steps_done, f.message));
    stopped[f.simulation] = true;
  }
  std::vector<py::ssize_t> completed;
  for (size_t i = 0; i < sims; ++i) {
    if (!stopped[i]) completed.push_back(static_cast<py::ssize_t>(i));
  }
  // the completed rows only: a failed simulation's rows after its failure hold no state
  const py::array_t<py::ssize_t> index(static_cast<py::ssize_t>(completed.size()),
                                       completed.data());
  py::dict results;
  for (const auto& item : arrays.Dict()) results[item.first] = item.second[index];
  results["simulations"] = index;

  py::object error = error_class(message);
  error.attr("simulation") = first.simulation;
  error.attr("steps_done") = first.steps_done;
  error.attr("failures") = listed;
  error.attr("results") = results;
  PyErr_SetObject(error_class.ptr(), error.ptr());
  throw py::error_already_set();
}

py::dict RolloutCall(const py::sequence& simulations, std::int64_t steps, const py::object& threads,
                     const py::object& controls) {
  // the simulations, held for the call (the caller's list may change while the GIL is released)
  const size_t n = simulations.size();
  if (n == 0) throw InputError("rollout: simulations = []: expected a list of Simulations");
  if (steps < 1) throw InputError(fmt::format("rollout: steps = {}: expected steps ≥ 1", steps));
  std::vector<py::object> held;
  std::vector<PySimulation*> sims;
  for (size_t i = 0; i < n; ++i) {
    py::object item = simulations[i];
    if (!py::isinstance<PySimulation>(item)) {
      throw InputError(fmt::format("rollout: simulations[{}] = {}: expected a Simulation", i,
                                   py::repr(item).cast<std::string>()));
    }
    PySimulation* sim = item.cast<PySimulation*>();
    for (size_t j = 0; j < i; ++j) {
      if (sims[j] == sim) {
        throw InputError(fmt::format(
            "rollout: simulations[{}] is simulations[{}]: expected distinct Simulations (each "
            "steps its own rows; make another Simulation of the scene)",
            i, j));
      }
    }
    held.push_back(std::move(item));
    sims.push_back(sim);
  }

  // equal body counts: the arrays stack the simulations
  const size_t bodies = sims[0]->scene->scene.bodies.size();
  for (size_t i = 1; i < n; ++i) {
    const engine::Scene& scene = sims[i]->scene->scene;
    if (scene.bodies.size() != bodies) {
      throw InputError(fmt::format(
          "rollout: simulations[{}] ({}) has {} bodies, simulations[0] ({}) {}: expected "
          "simulations of as many bodies each (the arrays stack them; roll out each body count "
          "in a call of its own)",
          i, scene.source, scene.bodies.size(), sims[0]->scene->scene.source, bodies));
    }
  }

  // threads: the machine's by default, at most one per simulation
  long thread_count = 0;
  if (threads.is_none()) {
    thread_count = std::max(1u, std::thread::hardware_concurrency());
  } else {
    thread_count = threads.cast<long>();
    if (thread_count < 1) {
      throw InputError(fmt::format(
          "rollout: threads = {}: expected an integer ≥ 1, or None for the machine's {}",
          thread_count, std::thread::hardware_concurrency()));
    }
  }
  thread_count = std::min(thread_count, static_cast<long>(n));

  // controls (n, steps, bodies, 6), as one C-ordered float64 array
  py::array_t<double, py::array::c_style | py::array::forcecast> wrenches;
  if (!controls.is_none()) {
    wrenches = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(controls);
    const std::vector<py::ssize_t> expected = {static_cast<py::ssize_t>(n), steps,
                                               static_cast<py::ssize_t>(bodies), 6};
    if (!wrenches || wrenches.ndim() != 4 ||
        !std::equal(expected.begin(), expected.end(), wrenches.shape())) {
      const std::string shape = wrenches ? py::str(wrenches.attr("shape")).cast<std::string>()
                                         : py::repr(controls).cast<std::string>();
      throw InputError(fmt::format(
          "rollout: controls of shape {}: expected an array of numbers of shape ({}, {}, {}, 6): "
          "per simulation, step and body the force (N, world, at the CM) and torque (N·m)",
          shape, n, steps, bodies));
    }
  }

  RolloutArrays arrays(static_cast<py::ssize_t>(n), steps, static_cast<py::ssize_t>(bodies));
  std::vector<RolloutJob> jobs(n);
  for (size_t i = 0; i < n; ++i) {
    RolloutJob& job = jobs[i];
    job.sim = &sims[i]->sim;
    job.mutex = &sims[i]->mutex;
    job.scene = &sims[i]->scene->scene;
    if (!controls.is_none()) {
      job.controls = wrenches.data() + i * static_cast<size_t>(steps) * bodies * 6;
    }
    job.rows = arrays.Rows(i, static_cast<size_t>(steps), bodies);
    CheckControls(job, i, steps);
  }

  // Ctrl-C stops every job's step in progress, undone, and Python's SIGINT handler runs (its
  // KeyboardInterrupt thrown from here); where the program's handler raises nothing, the jobs go
  // on from where they stood
  std::vector<RolloutFailure> failures;
  std::vector<RolloutProgress> progress(n);
  for (;;) {
    bool interrupted = false;
    {
      py::gil_scoped_release release;
      CancelFlag flag;
      const StepInterrupt guard(flag);
      std::vector<RolloutFailure> failed =
          Rollout(jobs, steps, static_cast<int>(thread_count), &flag, progress);
      failures.insert(failures.end(), std::make_move_iterator(failed.begin()),
                      std::make_move_iterator(failed.end()));
      interrupted = guard.interrupted();
    }
    if (!interrupted) break;
    HandOverInterrupt();
  }
  std::sort(failures.begin(), failures.end(), [](const RolloutFailure& a, const RolloutFailure& b) {
    return a.simulation < b.simulation;
  });
  if (!failures.empty()) RaiseFailures(failures, arrays, n, steps);
  return arrays.Dict();
}

}  // namespace

void BindRollout(py::module_& m, py::class_<PySimulation>& sim) {
  sim.def(
         "set_mass",
         [](PySimulation& self, const py::handle& body, const py::handle& mass,
            const py::object& inertia) {
           const std::lock_guard<std::mutex> lock(self.mutex);
           const int b = BodyIndex(self.sim.scene(), body, "set_mass");
           const double kg = ToDouble(mass, "set_mass: mass");
           std::optional<Eigen::Matrix3d> I;
           if (!inertia.is_none()) I = ToInertia(inertia, "set_mass");
           self.sim.SetMass(b, kg, I);
         },
         py::arg("body"), py::arg("mass"), py::arg("inertia") = py::none(),
         "Sets a dynamic body's (name or index) mass (kg) from the next step on, in this "
         "Simulation only (its Scene stays as loaded; reset() restores the scene's value). The "
         "inertia scales with the mass (a uniform density) unless `inertia` is given: 3 principal "
         "moments or a 3 × 3 matrix (kg·m², about the CM in body axes).\n"
         "Raises InputError with the loader's message for a kinematic body or a value the loader "
         "refuses; nothing changes then.")
      .def(
          "set_inertia",
          [](PySimulation& self, const py::handle& body, const py::handle& inertia) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            const int b = BodyIndex(self.sim.scene(), body, "set_inertia");
            self.sim.SetInertia(b, ToInertia(inertia, "set_inertia"));
          },
          py::arg("body"), py::arg("inertia"),
          "Sets a dynamic body's inertia (kg·m², about the CM in body axes): 3 principal moments "
          "(a diagonal) or a 3 × 3 symmetric positive definite matrix; as set_mass.")
      .def(
          "set_friction",
          [](PySimulation& self, const py::handle& contact, const py::object& mu,
             const py::object& e_t, const py::object& e_o, const py::object& e_r) {
            const std::lock_guard<std::mutex> lock(self.mutex);
            const int k = ContactIndex(self.sim.scene(), contact);
            Simulation::FrictionChange change;
            change.mu = OptionalDouble(mu, "set_friction: mu");
            change.e_t = OptionalDouble(e_t, "set_friction: e_t");
            change.e_o = OptionalDouble(e_o, "set_friction: e_o");
            if (py::isinstance<py::str>(e_r)) {
              if (e_r.cast<std::string>() != "patch") {
                throw InputError(
                    fmt::format("set_friction: e_r = {}: expected a length > 0 m or \"patch\"",
                                py::repr(e_r).cast<std::string>()));
              }
              change.e_r_patch = true;
            } else {
              change.e_r = OptionalDouble(e_r, "set_friction: e_r");
            }
            self.sim.SetFriction(k, change);
          },
          py::arg("contact"), py::arg("mu") = py::none(), py::arg("e_t") = py::none(),
          py::arg("e_o") = py::none(), py::arg("e_r") = py::none(),
          "Sets a contact's friction (named as in Scene.contact_names, 'box.ground', or by "
          "index) from the next step on, in this Simulation only: mu ≥ 0, the ellipsoid's e_t, "
          "e_o > 0 and e_r > 0 (m; a number replaces `e_r: patch`) or \"patch\" (the contact "
          "patch's, docs/scene_format.md); None keeps a value. reset() "
          "restores the scene's.\n"
          "Raises InputError with the loader's message for a value it refuses; nothing changes "
          "then.");

  m.def("rollout", &RolloutCall, py::arg("simulations"), py::arg("steps"),
        py::arg("threads") = py::none(), py::arg("controls") = py::none(),
        "Steps each Simulation of the list `steps` times on C++ threads without the GIL "
        "(threads: None for the machine's hardware threads) and returns a dict of numpy arrays "
        "of the state after each step: positions (n_sims, steps, n_bodies, 3), quaternions (..., "
        "4) (w, x, y, z), velocities, angular_velocities, time (n_sims, steps), converged "
        "(n_sims, steps) bool. The simulations may be of different scenes with as many bodies "
        "each, and are stepped on from their present states, each by one thread at a time; the "
        "numbers are those of step() in one thread, whatever `threads` is.\n"
        "controls: None or (n_sims, steps, n_bodies, 6): per step and body, force (N, world, at "
        "the CM) and torque (N·m) applied on that step as apply_wrench (a kinematic body's rows "
        "must be zero).\n"
        "Raises InputError for bad arguments before any step. When a simulation's step fails, "
        "it stops at its last good state and the others go on; then the first failure's "
        "SolverFailure (or ModelInvalid, InputError) is raised naming the simulation and step, "
        "with attributes simulation, steps_done, failures [(simulation, steps_done, message)] "
        "and results (the arrays of the completed simulations, their indices in "
        "results['simulations']).\n"
        "Ctrl-C stops every simulation's step in progress, undone, and raises "
        "KeyboardInterrupt with each at its last step done (a handler that raises nothing lets "
        "them go on).");
}

}  // namespace ecpsim::python
