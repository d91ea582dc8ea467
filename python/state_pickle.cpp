#include "python/state_pickle.h"

#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "common/errors.h"

namespace ecpsim::python {
namespace {

namespace py = pybind11;
using Eigen::Vector3d;

constexpr const char* kTag = "ecpsim.State";
// the layout below; a change of it (say, a new field of State) takes the next number, so an
// old pickle is refused by name rather than read wrongly
constexpr int kVersion = 2;             // 2: a hull warm start's trend
constexpr size_t kBodyNumbers = 13;     // p (3), q (w, x, y, z), v (3), w (3)
constexpr size_t kContactNumbers = 20;  // a1 (3), a2 (3), p_n p_t p_o p_r sigma, n t o (3 each)

void Append(std::vector<double>& out, const Vector3d& v) {
  out.insert(out.end(), v.data(), v.data() + 3);
}

Vector3d At(const std::vector<double>& in, size_t i) { return {in[i], in[i + 1], in[i + 2]}; }

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

Eigen::VectorXd ToEigen(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// `count` floats of a tuple entry, or an error naming it
std::vector<double> Numbers(const py::handle& value, size_t count, const std::string& what) {
  const auto numbers = value.cast<std::vector<double>>();
  if (numbers.size() != count) {
    throw InputError(
        fmt::format("State pickle: {}: {} numbers: expected {}", what, numbers.size(), count));
  }
  return numbers;
}

py::object WarmStartTuple(const engine::WarmStart& warm) {
  if (const auto* hull = std::get_if<engine::HullWarmStart>(&warm)) {
    const engine::SolutionTrend& trend = hull->trend;
    return py::make_tuple(
        "hull", hull->s, ToStd(hull->l_g), hull->window, ToStd(hull->l), hull->other_window,
        py::make_tuple(trend.h, trend.steps, ToStd(trend.first), ToStd(trend.second)));
  }
  if (const auto* patches = std::get_if<engine::MultiPatchWarmStart>(&warm)) {
    std::vector<std::vector<double>> parts;
    for (const Eigen::VectorXd& part : patches->parts) parts.push_back(ToStd(part));
    return py::make_tuple("multipatch", parts);
  }
  return py::none();
}

// a hull warm start's trend (h, steps, first, second), or an error naming the contact
engine::SolutionTrend TrendFromTuple(const py::handle& value, size_t contact) {
  const auto t = value.cast<py::tuple>();
  const std::string what = fmt::format("contacts[{}] warm start trend", contact);
  engine::SolutionTrend trend;
  if (t.size() != 4) {
    throw InputError(fmt::format("State pickle: {}: {} entries: expected (h, steps, first, second)",
                                 what, t.size()));
  }
  trend.h = t[0].cast<double>();
  trend.steps = t[1].cast<int>();
  if (trend.steps < 0 || trend.steps > 2) {
    throw InputError(
        fmt::format("State pickle: {}: steps = {}: expected 0, 1 or 2", what, trend.steps));
  }
  const size_t size = engine::SolutionTrend::kSize;
  const std::vector<double> first = Numbers(t[2], size, what + " first");
  const std::vector<double> second = Numbers(t[3], size, what + " second");
  trend.first = Eigen::Map<const engine::SolutionTrend::Point>(first.data());
  trend.second = Eigen::Map<const engine::SolutionTrend::Point>(second.data());
  return trend;
}

engine::WarmStart WarmStartFromTuple(const py::handle& value, size_t contact) {
  if (value.is_none()) return std::monostate();
  const auto t = value.cast<py::tuple>();
  const std::string kind = t.empty() ? "" : t[0].cast<std::string>();
  if (kind == "hull" && t.size() == 7) {
    engine::HullWarmStart hull;
    hull.s = t[1].cast<double>();
    hull.l_g = ToEigen(t[2].cast<std::vector<double>>());
    hull.window = t[3].cast<std::vector<int>>();
    hull.l = ToEigen(t[4].cast<std::vector<double>>());
    hull.other_window = t[5].cast<std::vector<int>>();
    hull.trend = TrendFromTuple(t[6], contact);
    return hull;
  }
  if (kind == "multipatch" && t.size() == 2) {
    engine::MultiPatchWarmStart patches;
    for (const auto& part : t[1].cast<std::vector<std::vector<double>>>()) {
      patches.parts.push_back(ToEigen(part));
    }
    return patches;
  }
  throw InputError(
      fmt::format("State pickle: contacts[{}] warm start: expected None, ('hull', "
                  "s, l_g, window, l, other_window, trend) or ('multipatch', parts)",
                  contact));
}

}  // namespace

py::tuple StateToTuple(const engine::State& state) {
  py::list bodies;
  for (const engine::BodyState& b : state.bodies) {
    std::vector<double> numbers;
    Append(numbers, b.p_WB);
    numbers.insert(numbers.end(), {b.Q_WB.w(), b.Q_WB.x(), b.Q_WB.y(), b.Q_WB.z()});
    Append(numbers, b.v_WB);
    Append(numbers, b.w_WB);
    bodies.append(py::cast(numbers));
  }
  py::list contacts;
  for (const engine::ContactState& c : state.contacts) {
    std::vector<double> numbers;
    Append(numbers, c.a1);
    Append(numbers, c.a2);
    numbers.insert(numbers.end(), {c.p_n, c.p_t, c.p_o, c.p_r, c.sigma});
    Append(numbers, c.n);
    Append(numbers, c.t);
    Append(numbers, c.o);
    contacts.append(py::make_tuple(numbers, WarmStartTuple(c.warm_start)));
  }
  return py::make_tuple(kTag, kVersion, state.t, state.steps, bodies, contacts);
}

engine::State StateFromTuple(const py::tuple& data) {
  if (data.size() != 6 || !py::isinstance<py::str>(data[0]) ||
      data[0].cast<std::string>() != kTag || !py::isinstance<py::int_>(data[1]) ||
      data[1].cast<int>() != kVersion) {
    throw InputError(
        fmt::format("State pickle {}: expected ('{}', {}, t, steps, bodies, contacts) "
                    "as pickled by this version of ecpsim",
                    py::repr(data[0]).cast<std::string>(), kTag, kVersion));
  }
  engine::State state;
  state.t = data[2].cast<double>();
  state.steps = data[3].cast<std::int64_t>();
  const auto bodies = data[4].cast<py::list>();
  for (size_t i = 0; i < bodies.size(); ++i) {
    const std::vector<double> x = Numbers(bodies[i], kBodyNumbers, fmt::format("bodies[{}]", i));
    engine::BodyState& b = state.bodies.emplace_back();
    b.p_WB = At(x, 0);
    b.Q_WB = Eigen::Quaterniond(x[3], x[4], x[5], x[6]);
    b.v_WB = At(x, 7);
    b.w_WB = At(x, 10);
  }
  const auto contacts = data[5].cast<py::list>();
  for (size_t i = 0; i < contacts.size(); ++i) {
    const auto entry = contacts[i].cast<py::tuple>();
    if (entry.size() != 2) {
      throw InputError(
          fmt::format("State pickle: contacts[{}]: expected (numbers, warm start)", i));
    }
    const std::vector<double> x =
        Numbers(entry[0], kContactNumbers, fmt::format("contacts[{}]", i));
    engine::ContactState& c = state.contacts.emplace_back();
    c.a1 = At(x, 0);
    c.a2 = At(x, 3);
    c.p_n = x[6], c.p_t = x[7], c.p_o = x[8], c.p_r = x[9], c.sigma = x[10];
    c.n = At(x, 11);
    c.t = At(x, 14);
    c.o = At(x, 17);
    c.warm_start = WarmStartFromTuple(entry[1], i);
  }
  return state;
}

}  // namespace ecpsim::python
