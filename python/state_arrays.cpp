#include "python/state_arrays.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common/errors.h"
#include "engine/report/contact_wrench.h"
#include "engine/report/trajectory_columns.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/scene_limits.h"
#include "python/conversions.h"

namespace py = pybind11;

namespace ecpsim::python {
namespace {

using Eigen::Vector3d;

// a contact whose normal impulse is below this fraction of the body's impulse scale
// m (|g| h + |v|) carries no load: round-off of a complementarity solution that is exactly 0
constexpr double kSeparatedImpulseFraction = 1e-9;  // dimensionless
// a contact whose slip multiplier σ exceeds this fraction of the body's velocity scale
// |g| h + |v| slides; a sticking one's σ is 0 up to the solver's tolerance, or the hull model's
// creep between bodies (kStickCreepFraction, engine/models/hull_model.h)
constexpr double kSlidingSlipFraction = 1e-6;  // dimensionless

int FieldWidth(BodyField field) { return field == BodyField::kQuaternion ? 4 : 3; }

const char* ContactMode(const engine::Scene& scene, const engine::State& state,
                        const engine::ContactPair& pair, const engine::ContactState& c) {
  const engine::Body& body = scene.bodies[pair.body];
  const double velocity_scale =
      scene.gravity.norm() * scene.h + state.bodies[pair.body].v_WB.norm();
  if (c.p_n <= kSeparatedImpulseFraction * body.mass * velocity_scale) return "separated";
  return c.sigma > kSlidingSlipFraction * velocity_scale ? "sliding" : "sticking";
}

}  // namespace

std::string ContactName(const engine::Scene& scene, const engine::ContactPair& pair) {
  const std::string& other =
      pair.WithBody() ? scene.bodies[pair.other_body].name : scene.obstacles[pair.obstacle].name;
  const auto part = [](int index) {
    return index < 0 ? std::string() : fmt::format("[{}]", index);
  };
  return scene.bodies[pair.body].name + part(pair.part) + "." + other + part(pair.other_part);
}

py::array_t<double> BodyArray(const engine::State& state, BodyField field) {
  const int width = FieldWidth(field);
  py::array_t<double> a(
      {static_cast<py::ssize_t>(state.bodies.size()), static_cast<py::ssize_t>(width)});
  auto out = a.mutable_unchecked<2>();
  for (size_t b = 0; b < state.bodies.size(); ++b) {
    const engine::BodyState& s = state.bodies[b];
    const py::ssize_t i = static_cast<py::ssize_t>(b);
    switch (field) {
      case BodyField::kPosition:
        for (int k = 0; k < 3; ++k) out(i, k) = s.p_WB[k];
        break;
      case BodyField::kQuaternion:
        // w, x, y, z: the CSV's qw qx qy qz
        out(i, 0) = s.Q_WB.w(), out(i, 1) = s.Q_WB.x(), out(i, 2) = s.Q_WB.y(),
               out(i, 3) = s.Q_WB.z();
        break;
      case BodyField::kVelocity:
        for (int k = 0; k < 3; ++k) out(i, k) = s.v_WB[k];
        break;
      case BodyField::kAngularVelocity:
        for (int k = 0; k < 3; ++k) out(i, k) = s.w_WB[k];
        break;
    }
  }
  return a;
}

const char* FieldName(BodyField field) {
  switch (field) {
    case BodyField::kPosition:
      return "positions";
    case BodyField::kQuaternion:
      return "quaternions";
    case BodyField::kVelocity:
      return "velocities";
    case BodyField::kAngularVelocity:
      return "angular_velocities";
  }
  return "?";
}

void SetBodyArray(const engine::Scene& scene, engine::State& state, BodyField field,
                  const py::handle& value) {
  const int width = FieldWidth(field);
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  const size_t n = state.bodies.size();
  if (!a || a.ndim() != 2 || a.shape(0) != static_cast<py::ssize_t>(n) || a.shape(1) != width) {
    throw InputError(
        fmt::format("{}: expected an array of shape ({}, {})", FieldName(field), n, width));
  }
  const auto in = a.unchecked<2>();
  std::vector<engine::BodyState> bodies = state.bodies;
  for (size_t b = 0; b < n; ++b) {
    const py::ssize_t i = static_cast<py::ssize_t>(b);
    engine::BodyState& s = bodies[b];
    if (field == BodyField::kQuaternion) {
      const Eigen::Quaterniond q(in(i, 0), in(i, 1), in(i, 2), in(i, 3));
      if (!q.coeffs().allFinite() || q.norm() == 0) {
        throw InputError(
            fmt::format("quaternions[{}] ({}): expected a finite, non-zero "
                        "quaternion (w, x, y, z)",
                        b, scene.bodies[b].name));
      }
      s.Q_WB = q.normalized();
      continue;
    }
    const Vector3d v(in(i, 0), in(i, 1), in(i, 2));
    for (int k = 0; k < 3; ++k) {
      const std::string problem = engine::OutOfMagnitude(v[k]);
      if (!problem.empty()) {
        throw InputError(fmt::format("{}[{}] ({}) = [{}, {}, {}]: expected {}", FieldName(field), b,
                                     scene.bodies[b].name, v.x(), v.y(), v.z(), problem));
      }
    }
    (field == BodyField::kPosition ? s.p_WB : field == BodyField::kVelocity ? s.v_WB : s.w_WB) = v;
  }
  for (size_t b = 0; b < n; ++b) {
    const engine::BodyState &now = state.bodies[b], &next = bodies[b];
    const bool same = now.p_WB == next.p_WB && now.Q_WB.coeffs() == next.Q_WB.coeffs() &&
                      now.v_WB == next.v_WB && now.w_WB == next.w_WB;
    if (scene.bodies[b].IsKinematic() && !same) {
      throw InputError(
          fmt::format("{}[{}]: body '{}' is kinematic: expected its row unchanged "
                      "(set_kinematic_target moves it)",
                      FieldName(field), b, scene.bodies[b].name));
    }
  }
  if (field == BodyField::kPosition || field == BodyField::kQuaternion) {
    engine::State posed = state;
    posed.bodies = bodies;
    RequireApart(scene, posed, FieldName(field));
  }
  state.bodies = std::move(bodies);
}

void RequireApart(const engine::Scene& scene, const engine::State& state,
                  const std::string& where) {
  const std::optional<engine::Overlap> overlap = engine::FindOverlap(scene, state);
  if (!overlap) return;
  const std::string other =
      overlap->obstacle >= 0 ? fmt::format("obstacle '{}'", scene.obstacles[overlap->obstacle].name)
                             : fmt::format("body '{}'", scene.bodies[overlap->other_body].name);
  throw InputError(fmt::format(
      "{}: body '{}' is {:.3g} m inside {}, more than {:.3g} m ({:g} × the size {:.3g} m): "
      "expected poses apart (or the scene's bodies[{}].allow_initial_penetration: true)",
      where, scene.bodies[overlap->body].name, overlap->depth, other, overlap->tolerance,
      engine::kInitialPenetrationTolerance, overlap->size, overlap->body));
}

py::dict ReportDict(const engine::Scene& scene, const engine::StepReport& report) {
  py::dict d;
  d["converged"] = report.converged;
  d["iterations"] = report.iterations;
  d["residual"] = report.residual;
  d["retries"] = report.retries;
  d["substeps"] = report.substeps;
  // what solved each body's step, by name (empty before the first step)
  py::dict models;
  for (size_t b = 0; b < report.models.size() && b < scene.bodies.size(); ++b)
    models[py::str(scene.bodies[b].name)] = engine::StepModelName(report.models[b]);
  d["models"] = models;
  return d;
}

py::list ContactList(const engine::Scene& scene, const engine::State& state,
                     const engine::StepReport& report) {
  py::list contacts;
  const double h = scene.h;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const engine::ContactPair& pair = scene.contacts[k];
    const engine::ContactState& c = state.contacts[k];
    py::dict d;
    d["name"] = ContactName(scene, pair);
    d["body"] = scene.bodies[pair.body].name;
    d["other"] =
        pair.WithBody() ? scene.bodies[pair.other_body].name : scene.obstacles[pair.obstacle].name;
    d["other_is_body"] = pair.WithBody();
    // the parts touching (Body::parts indices; None: the hull)
    d["part"] = pair.part < 0 ? py::object(py::none()) : py::object(py::int_(pair.part));
    d["other_part"] =
        pair.other_part < 0 ? py::object(py::none()) : py::object(py::int_(pair.other_part));
    // which set of a pair under decomposition: auto the contact is in (engine/auto_sides.h)
    d["sides"] = pair.sides == engine::SideChoice::kHulls   ? "hulls"
                 : pair.sides == engine::SideChoice::kParts ? "parts"
                                                            : "fixed";
    d["a1"] = Array(c.a1);
    d["a2"] = Array(c.a2);
    d["normal"] = Array(c.n);
    d["tangent"] = Array(c.t);
    d["tangent2"] = Array(c.o);
    d["p_n"] = c.p_n;
    d["p_t"] = c.p_t;
    d["p_o"] = c.p_o;
    d["p_r"] = c.p_r;
    d["sigma"] = c.sigma;
    d["f_n"] = c.p_n / h;
    d["f_t"] = c.p_t / h;
    d["f_o"] = c.p_o / h;
    d["f_r"] = c.p_r / h;
    d["force"] = Array(Vector3d((c.n * c.p_n + c.t * c.p_t + c.o * c.p_o) / h));
    d["mode"] = ContactMode(scene, state, pair, c);
    // what solved the step of the contact's body; before the first step, the scene's model
    d["model"] = report.models.empty() ? engine::ContactModelName(scene.model)
                                       : engine::StepModelName(report.models[pair.body]);
    d["friction"] = FrictionDict(pair.friction);
    contacts.append(d);
  }
  return contacts;
}

py::array_t<double> SensorArray(const engine::Scene& scene, const engine::State& state, int body) {
  const engine::Wrench w = engine::SensorWrench(scene, state, body);
  const double values[6] = {w.force.x(),  w.force.y(),  w.force.z(),
                            w.moment.x(), w.moment.y(), w.moment.z()};
  return Array(values, {6});
}

py::dict ContactArrays(const engine::Scene& scene, const engine::State& state,
                       const engine::StepReport& report) {
  const size_t count = scene.contacts.size();
  const py::ssize_t rows = static_cast<py::ssize_t>(count);
  const double h = scene.h;
  // each array written through its pointer: a per-row accessor costs more than the numbers
  const auto vectors = [&](auto&& of) {
    py::array_t<double> a({rows, py::ssize_t{3}});
    double* out = a.mutable_data();
    for (size_t k = 0; k < count; ++k) {
      const Vector3d v = of(state.contacts[k]);
      out[3 * k] = v.x(), out[3 * k + 1] = v.y(), out[3 * k + 2] = v.z();
    }
    return a;
  };
  const auto scalars = [&](auto&& of) {
    py::array_t<double> a(rows);
    double* out = a.mutable_data();
    for (size_t k = 0; k < count; ++k) out[k] = of(state.contacts[k]);
    return a;
  };
  using C = engine::ContactState;
  py::dict d;
  py::list names, bodies, others, modes, models;
  py::array_t<bool> other_is_body(rows);
  for (size_t k = 0; k < count; ++k) {
    const engine::ContactPair& pair = scene.contacts[k];
    names.append(ContactName(scene, pair));
    bodies.append(scene.bodies[pair.body].name);
    others.append(pair.WithBody() ? scene.bodies[pair.other_body].name
                                  : scene.obstacles[pair.obstacle].name);
    other_is_body.mutable_data()[k] = pair.WithBody();
    modes.append(ContactMode(scene, state, pair, state.contacts[k]));
    models.append(report.models.empty() ? engine::ContactModelName(scene.model)
                                        : engine::StepModelName(report.models[pair.body]));
  }
  d["name"] = names;
  d["body"] = bodies;
  d["other"] = others;
  d["other_is_body"] = other_is_body;
  d["a1"] = vectors([](const C& c) { return c.a1; });
  d["a2"] = vectors([](const C& c) { return c.a2; });
  d["normal"] = vectors([](const C& c) { return c.n; });
  d["tangent"] = vectors([](const C& c) { return c.t; });
  d["tangent2"] = vectors([](const C& c) { return c.o; });
  d["p_n"] = scalars([](const C& c) { return c.p_n; });
  d["p_t"] = scalars([](const C& c) { return c.p_t; });
  d["p_o"] = scalars([](const C& c) { return c.p_o; });
  d["p_r"] = scalars([](const C& c) { return c.p_r; });
  d["sigma"] = scalars([](const C& c) { return c.sigma; });
  d["f_n"] = scalars([h](const C& c) { return c.p_n / h; });
  d["f_t"] = scalars([h](const C& c) { return c.p_t / h; });
  d["f_o"] = scalars([h](const C& c) { return c.p_o / h; });
  d["f_r"] = scalars([h](const C& c) { return c.p_r / h; });
  d["force"] =
      vectors([h](const C& c) { return Vector3d((c.n * c.p_n + c.t * c.p_t + c.o * c.p_o) / h); });
  d["mode"] = modes;
  d["model"] = models;
  return d;
}

}  // namespace ecpsim::python
