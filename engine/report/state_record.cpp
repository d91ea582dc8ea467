#include "engine/report/state_record.h"

#include <cerrno>
#include <cstdlib>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/models/hull_warm_start.h"
#include "engine/models/multipatch_warm_start.h"

namespace ecpsim::engine {

using nlohmann::json;

json ExactJson(double value) { return fmt::format("{:a}", value); }

json ExactJson(const Eigen::VectorXd& values) {
  json list = json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) list.push_back(ExactJson(values[i]));
  return list;
}

double ReadExact(const json& node, const std::string& key) {
  const std::string text = node.get<std::string>();
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE) {
    throw InputError(fmt::format("{} = \"{}\": expected a hexadecimal float", key, text));
  }
  return value;
}

Eigen::VectorXd ReadExactVector(const json& node, const std::string& key, Eigen::Index size) {
  if (!node.is_array() || (size >= 0 && static_cast<Eigen::Index>(node.size()) != size)) {
    throw InputError(fmt::format("{}: expected a list of {} hexadecimal floats", key,
                                 size >= 0 ? fmt::format("{}", size) : std::string("any number")));
  }
  Eigen::VectorXd values(node.size());
  for (std::size_t i = 0; i < node.size(); ++i) {
    values[i] = ReadExact(node[i], fmt::format("{}[{}]", key, i));
  }
  return values;
}

namespace {

Eigen::Vector3d ReadVector3(const json& node, const std::string& key) {
  return ReadExactVector(node, key, 3);
}

json BodyJson(const BodyState& b) {
  const Eigen::Vector4d q(b.Q_WB.w(), b.Q_WB.x(), b.Q_WB.y(), b.Q_WB.z());
  return {{"p_WB", ExactJson(b.p_WB)},
          {"Q_WB_wxyz", ExactJson(q)},
          {"v_WB", ExactJson(b.v_WB)},
          {"w_WB", ExactJson(b.w_WB)}};
}

BodyState ReadBody(const json& node, const std::string& key) {
  BodyState b;
  b.p_WB = ReadVector3(node.at("p_WB"), key + ".p_WB");
  const Eigen::VectorXd q = ReadExactVector(node.at("Q_WB_wxyz"), key + ".Q_WB_wxyz", 4);
  b.Q_WB = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  b.v_WB = ReadVector3(node.at("v_WB"), key + ".v_WB");
  b.w_WB = ReadVector3(node.at("w_WB"), key + ".w_WB");
  return b;
}

json TrendJson(const SolutionTrend& trend) {
  return {{"h", ExactJson(trend.h)},
          {"steps", trend.steps},
          {"first", ExactJson(Eigen::VectorXd(trend.first))},
          {"second", ExactJson(Eigen::VectorXd(trend.second))}};
}

SolutionTrend ReadTrend(const json& node, const std::string& key) {
  SolutionTrend trend;
  trend.h = ReadExact(node.at("h"), key + ".h");
  trend.steps = node.at("steps").get<int>();
  if (trend.steps < 0 || trend.steps > 2) {
    throw InputError(fmt::format("{}.steps = {}: expected 0, 1 or 2", key, trend.steps));
  }
  trend.first = ReadExactVector(node.at("first"), key + ".first", SolutionTrend::kSize);
  trend.second = ReadExactVector(node.at("second"), key + ".second", SolutionTrend::kSize);
  return trend;
}

// {"model": "hull", ...} with the model's unknowns, or null for no warm start
json WarmStartJson(const WarmStart& warm) {
  if (const auto* hull = warm.Get<HullWarmStart>()) {
    return {{"model", "hull"},
            {"s", ExactJson(hull->s)},
            {"l_g", ExactJson(hull->l_g)},
            {"window", hull->window},
            {"l", ExactJson(hull->l)},
            {"other_window", hull->other_window},
            {"trend", TrendJson(hull->trend)}};
  }
  if (const auto* multipatch = warm.Get<MultiPatchWarmStart>()) {
    json parts = json::array();
    for (const Eigen::VectorXd& part : multipatch->parts) parts.push_back(ExactJson(part));
    return {{"model", "multipatch"}, {"parts", parts}};
  }
  return nullptr;
}

WarmStart ReadWarmStart(const json& node, const std::string& key) {
  WarmStart warm;
  if (node.is_null()) return warm;
  const std::string model = node.at("model").get<std::string>();
  if (model == "hull") {
    HullWarmStart hull;
    hull.s = ReadExact(node.at("s"), key + ".s");
    hull.l_g = ReadExactVector(node.at("l_g"), key + ".l_g", -1);
    hull.window = node.at("window").get<std::vector<int>>();
    hull.l =
        ReadExactVector(node.at("l"), key + ".l", static_cast<Eigen::Index>(hull.window.size()));
    // a moving G's window, by which l_G is carried to the next step's (empty: a fixed G)
    hull.other_window = node.at("other_window").get<std::vector<int>>();
    hull.trend = ReadTrend(node.at("trend"), key + ".trend");
    warm.Set(std::move(hull));
    return warm;
  }
  if (model == "multipatch") {
    MultiPatchWarmStart multipatch;
    const json& parts = node.at("parts");
    for (std::size_t i = 0; i < parts.size(); ++i)
      multipatch.parts.push_back(
          ReadExactVector(parts[i], fmt::format("{}.parts[{}]", key, i), -1));
    warm.Set(std::move(multipatch));
    return warm;
  }
  throw InputError(
      fmt::format("{}.model = \"{}\": expected \"hull\" or \"multipatch\"", key, model));
}

json ContactJson(const ContactState& c) {
  return {{"a1", ExactJson(c.a1)},
          {"a2", ExactJson(c.a2)},
          {"p_n", ExactJson(c.p_n)},
          {"p_t", ExactJson(c.p_t)},
          {"p_o", ExactJson(c.p_o)},
          {"p_r", ExactJson(c.p_r)},
          {"sigma", ExactJson(c.sigma)},
          {"n", ExactJson(c.n)},
          {"t", ExactJson(c.t)},
          {"o", ExactJson(c.o)},
          {"warm_start", WarmStartJson(c.warm_start)}};
}

ContactState ReadContact(const json& node, const std::string& key) {
  ContactState c;
  c.a1 = ReadVector3(node.at("a1"), key + ".a1");
  c.a2 = ReadVector3(node.at("a2"), key + ".a2");
  c.p_n = ReadExact(node.at("p_n"), key + ".p_n");
  c.p_t = ReadExact(node.at("p_t"), key + ".p_t");
  c.p_o = ReadExact(node.at("p_o"), key + ".p_o");
  c.p_r = ReadExact(node.at("p_r"), key + ".p_r");
  c.sigma = ReadExact(node.at("sigma"), key + ".sigma");
  c.n = ReadVector3(node.at("n"), key + ".n");
  c.t = ReadVector3(node.at("t"), key + ".t");
  c.o = ReadVector3(node.at("o"), key + ".o");
  c.warm_start = ReadWarmStart(node.at("warm_start"), key + ".warm_start");
  return c;
}

// {"steps", "models", "in_step"}: the sleep rule's memory, models by name
json RestJson(const RestRecord& rest) {
  json models = json::array();
  for (StepModel model : rest.models) models.push_back(StepModelName(model));
  json residuals = json::array();
  for (double residual : rest.residuals) residuals.push_back(ExactJson(residual));
  return {{"steps", rest.steps},
          {"models", models},
          {"residuals", residuals},
          {"in_step", std::vector<int>(rest.in_step.begin(), rest.in_step.end())}};
}

RestRecord ReadRest(const json& node, const std::string& key) {
  RestRecord rest;
  rest.steps = node.at("steps").get<std::vector<std::int64_t>>();
  for (std::int64_t steps : rest.steps) {
    if (steps < 0)
      throw InputError(fmt::format("{}.steps: {}: expected counts >= 0", key, steps));
  }
  const json& models = node.at("models");
  for (std::size_t i = 0; i < models.size(); ++i) {
    const std::string name = models[i].get<std::string>();
    int m = 0;
    while (m < kNumStepModels && name != StepModelName(static_cast<StepModel>(m))) ++m;
    if (m == kNumStepModels) {
      throw InputError(fmt::format("{}.models[{}] = \"{}\": expected a model's name (free, "
                                   "planar, hull, multipatch, point, kinematic)",
                                   key, i, name));
    }
    rest.models.push_back(static_cast<StepModel>(m));
  }
  const Eigen::VectorXd residuals = ReadExactVector(node.at("residuals"), key + ".residuals", -1);
  rest.residuals.assign(residuals.data(), residuals.data() + residuals.size());
  for (int in_step : node.at("in_step").get<std::vector<int>>())
    rest.in_step.push_back(in_step != 0);
  return rest;
}

}  // namespace

json StateRecord(const State& state) {
  json bodies = json::array(), contacts = json::array();
  for (const BodyState& b : state.bodies) bodies.push_back(BodyJson(b));
  for (const ContactState& c : state.contacts) contacts.push_back(ContactJson(c));
  return {{"t", ExactJson(state.t)},
          {"steps", state.steps},
          {"bodies", bodies},
          {"contacts", contacts},
          {"rest", RestJson(state.rest)}};
}

State StateFromRecord(const json& record, const std::string& where) {
  try {
    State state;
    state.t = ReadExact(record.at("t"), where + ".t");
    state.steps = record.at("steps").get<std::int64_t>();
    const json& bodies = record.at("bodies");
    for (std::size_t i = 0; i < bodies.size(); ++i)
      state.bodies.push_back(ReadBody(bodies.at(i), fmt::format("{}.bodies[{}]", where, i)));
    const json& contacts = record.at("contacts");
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      state.contacts.push_back(
          ReadContact(contacts.at(i), fmt::format("{}.contacts[{}]", where, i)));
    }
    // (records written before sleeping islands have none: every body awake)
    if (record.contains("rest")) state.rest = ReadRest(record.at("rest"), where + ".rest");
    return state;
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
}

}  // namespace ecpsim::engine
