#include "app/checkpoint.h"

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "common/errors.h"

namespace ecpsim::app {
namespace {

using nlohmann::json;

// the format's version: a reader refuses any other (a changed State means a new version)
constexpr int kFormat = 3;  // 2: warm starts typed by model; 3: a hull warm start's trend

// exact doubles: C99 hexadecimal floats ("0x1.999999999999ap-4") read back to the same bits,
// infinities and NaN included
json Exact(double value) { return fmt::format("{:a}", value); }

json Exact(const Eigen::VectorXd& values) {
  json list = json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) list.push_back(Exact(values[i]));
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

Eigen::Vector3d ReadVector3(const json& node, const std::string& key) {
  return ReadExactVector(node, key, 3);
}

json BodyJson(const engine::BodyState& b) {
  const Eigen::Vector4d q(b.Q_WB.w(), b.Q_WB.x(), b.Q_WB.y(), b.Q_WB.z());
  return {{"p_WB", Exact(b.p_WB)},
          {"Q_WB_wxyz", Exact(q)},
          {"v_WB", Exact(b.v_WB)},
          {"w_WB", Exact(b.w_WB)}};
}

engine::BodyState ReadBody(const json& node, const std::string& key) {
  engine::BodyState b;
  b.p_WB = ReadVector3(node.at("p_WB"), key + ".p_WB");
  const Eigen::VectorXd q = ReadExactVector(node.at("Q_WB_wxyz"), key + ".Q_WB_wxyz", 4);
  b.Q_WB = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  b.v_WB = ReadVector3(node.at("v_WB"), key + ".v_WB");
  b.w_WB = ReadVector3(node.at("w_WB"), key + ".w_WB");
  return b;
}

json TrendJson(const engine::SolutionTrend& trend) {
  return {{"h", Exact(trend.h)},
          {"steps", trend.steps},
          {"first", Exact(Eigen::VectorXd(trend.first))},
          {"second", Exact(Eigen::VectorXd(trend.second))}};
}

engine::SolutionTrend ReadTrend(const json& node, const std::string& key) {
  engine::SolutionTrend trend;
  trend.h = ReadExact(node.at("h"), key + ".h");
  trend.steps = node.at("steps").get<int>();
  if (trend.steps < 0 || trend.steps > 2) {
    throw InputError(fmt::format("{}.steps = {}: expected 0, 1 or 2", key, trend.steps));
  }
  trend.first = ReadExactVector(node.at("first"), key + ".first", engine::SolutionTrend::kSize);
  trend.second = ReadExactVector(node.at("second"), key + ".second", engine::SolutionTrend::kSize);
  return trend;
}

// {"model": "hull", ...} with the model's unknowns, or null for no warm start
json WarmStartJson(const engine::WarmStart& warm) {
  if (const auto* hull = std::get_if<engine::HullWarmStart>(&warm)) {
    return {{"model", "hull"},
            {"s", Exact(hull->s)},
            {"l_g", Exact(hull->l_g)},
            {"window", hull->window},
            {"l", Exact(hull->l)},
            {"other_window", hull->other_window},
            {"trend", TrendJson(hull->trend)}};
  }
  if (const auto* multipatch = std::get_if<engine::MultiPatchWarmStart>(&warm)) {
    json parts = json::array();
    for (const Eigen::VectorXd& part : multipatch->parts) parts.push_back(Exact(part));
    return {{"model", "multipatch"}, {"parts", parts}};
  }
  return nullptr;
}

engine::WarmStart ReadWarmStart(const json& node, const std::string& key) {
  if (node.is_null()) return std::monostate();
  const std::string model = node.at("model").get<std::string>();
  if (model == "hull") {
    engine::HullWarmStart hull;
    hull.s = ReadExact(node.at("s"), key + ".s");
    hull.l_g = ReadExactVector(node.at("l_g"), key + ".l_g", -1);
    hull.window = node.at("window").get<std::vector<int>>();
    hull.l =
        ReadExactVector(node.at("l"), key + ".l", static_cast<Eigen::Index>(hull.window.size()));
    // a moving G's window, by which l_G is carried to the next step's (empty: a fixed G)
    hull.other_window = node.at("other_window").get<std::vector<int>>();
    hull.trend = ReadTrend(node.at("trend"), key + ".trend");
    return hull;
  }
  if (model == "multipatch") {
    engine::MultiPatchWarmStart multipatch;
    const json& parts = node.at("parts");
    for (std::size_t i = 0; i < parts.size(); ++i)
      multipatch.parts.push_back(
          ReadExactVector(parts[i], fmt::format("{}.parts[{}]", key, i), -1));
    return multipatch;
  }
  throw InputError(
      fmt::format("{}.model = \"{}\": expected \"hull\" or \"multipatch\"", key, model));
}

json ContactJson(const engine::ContactState& c) {
  return {{"a1", Exact(c.a1)},
          {"a2", Exact(c.a2)},
          {"p_n", Exact(c.p_n)},
          {"p_t", Exact(c.p_t)},
          {"p_o", Exact(c.p_o)},
          {"p_r", Exact(c.p_r)},
          {"sigma", Exact(c.sigma)},
          {"n", Exact(c.n)},
          {"t", Exact(c.t)},
          {"o", Exact(c.o)},
          {"warm_start", WarmStartJson(c.warm_start)}};
}

engine::ContactState ReadContact(const json& node, const std::string& key) {
  engine::ContactState c;
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

json TotalsJson(const RunTotals& totals) {
  json sample = json::array();
  for (double us : totals.step_us.sample()) sample.push_back(Exact(us));
  return {{"steps", totals.steps},
          {"retries", totals.retries},
          {"iterations", totals.iterations},
          {"iterations_max", totals.iterations_max},
          {"residual_max", Exact(totals.residual_max)},
          {"substeps_max", totals.substeps_max},
          {"max_penetration", Exact(totals.max_penetration)},
          {"all_converged", totals.all_converged},
          {"wall_s", Exact(totals.wall_s)},
          {"step_us_count", totals.step_us.count()},
          {"model_steps", totals.model_steps},
          {"step_us_sample", sample}};
}

RunTotals ReadTotals(const json& node) {
  RunTotals totals;
  totals.steps = node.at("steps").get<long>();
  totals.retries = node.at("retries").get<long>();
  totals.iterations = node.at("iterations").get<long>();
  totals.iterations_max = node.at("iterations_max").get<int>();
  totals.residual_max = ReadExact(node.at("residual_max"), "totals.residual_max");
  totals.substeps_max = node.at("substeps_max").get<int>();
  totals.max_penetration = ReadExact(node.at("max_penetration"), "totals.max_penetration");
  totals.all_converged = node.at("all_converged").get<bool>();
  totals.wall_s = ReadExact(node.at("wall_s"), "totals.wall_s");
  // a checkpoint of a run before `model: auto` counted no models
  if (node.contains("model_steps"))
    totals.model_steps = node.at("model_steps").get<std::array<long, engine::kNumStepModels>>();
  const Eigen::VectorXd sample =
      ReadExactVector(node.at("step_us_sample"), "totals.step_us_sample", -1);
  totals.step_us =
      ReservoirMedian(std::vector<double>(sample.data(), sample.data() + sample.size()),
                      node.at("step_us_count").get<std::int64_t>());
  return totals;
}

}  // namespace

void WriteCheckpoint(const std::string& path, const Checkpoint& checkpoint) {
  json bodies = json::array(), contacts = json::array();
  for (const engine::BodyState& b : checkpoint.state.bodies) bodies.push_back(BodyJson(b));
  for (const engine::ContactState& c : checkpoint.state.contacts) {
    contacts.push_back(ContactJson(c));
  }
  const json file = {
      {"format", kFormat},
      {"origin", checkpoint.origin},
      // readable, for people; the exact time is state.t
      {"t", checkpoint.state.t},
      {"rows", checkpoint.rows},
      {"totals", TotalsJson(checkpoint.totals)},
      {"state",
       {{"t", Exact(checkpoint.state.t)},
        {"steps", checkpoint.state.steps},
        {"bodies", bodies},
        {"contacts", contacts}}},
  };
  WriteFileAtomically(path, file.dump(1) + "\n");
}

Checkpoint ReadCheckpoint(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(
        fmt::format("{}: no checkpoint there, nothing to resume (a run leaves one "
                    "only when it stops early: Ctrl-C, SIGTERM or a solver failure)",
                    path));
  }
  try {
    const json file = json::parse(in);
    if (file.at("format") != kFormat) {
      throw InputError(
          fmt::format("format = {}: expected {} (written by another version of "
                      "ecpsim)",
                      file.at("format").dump(), kFormat));
    }
    Checkpoint checkpoint;
    checkpoint.origin = file.at("origin");
    if (!checkpoint.origin.is_object() || !checkpoint.origin.contains("arguments")) {
      throw InputError(
          fmt::format("origin = {}: expected how the run was started", checkpoint.origin.dump()));
    }
    checkpoint.rows = file.at("rows").get<long>();
    checkpoint.totals = ReadTotals(file.at("totals"));
    const json& state = file.at("state");
    checkpoint.state.t = ReadExact(state.at("t"), "state.t");
    checkpoint.state.steps = state.at("steps").get<std::int64_t>();
    for (std::size_t i = 0; i < state.at("bodies").size(); ++i) {
      checkpoint.state.bodies.push_back(
          ReadBody(state["bodies"][i], fmt::format("state.bodies[{}]", i)));
    }
    for (std::size_t i = 0; i < state.at("contacts").size(); ++i) {
      checkpoint.state.contacts.push_back(
          ReadContact(state["contacts"][i], fmt::format("state.contacts[{}]", i)));
    }
    if (checkpoint.totals.steps < 0 || checkpoint.rows < 1) {
      throw InputError(fmt::format("steps = {}, rows = {}: expected steps >= 0 and rows >= 1",
                                   checkpoint.totals.steps, checkpoint.rows));
    }
    return checkpoint;
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: not a checkpoint of ecpsim ({})", path, e.what()));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: not a checkpoint of ecpsim ({})", path, e.what()));
  }
}

void CheckFitsScene(const Checkpoint& checkpoint, const engine::Scene& scene,
                    const std::string& path) {
  if (checkpoint.state.bodies.size() != scene.bodies.size() ||
      checkpoint.state.contacts.size() != scene.contacts.size()) {
    throw InputError(
        fmt::format("{}: a state of {} bodies and {} contacts; the scene has {} and "
                    "{}",
                    path, checkpoint.state.bodies.size(), checkpoint.state.contacts.size(),
                    scene.bodies.size(), scene.contacts.size()));
  }
}

}  // namespace ecpsim::app
