#include "app/checkpoint.h"

#include <filesystem>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "engine/report/state_record.h"

namespace ecpsim::app {
namespace {

using engine::ExactJson;
using engine::ReadExact;
using engine::ReadExactVector;
using nlohmann::json;

// the format's version: a reader refuses any other (a changed State means a new version)
// 2: warm starts typed by model; 3: a hull warm start's trend; 4: the step model "parts"
constexpr int kFormat = 4;

json TotalsJson(const RunTotals& totals) {
  json sample = json::array();
  for (double us : totals.step_us.sample()) sample.push_back(ExactJson(us));
  return {{"steps", totals.steps},
          {"retries", totals.retries},
          {"iterations", totals.iterations},
          {"iterations_max", totals.iterations_max},
          {"residual_max", ExactJson(totals.residual_max)},
          {"substeps_max", totals.substeps_max},
          {"max_penetration", ExactJson(totals.max_penetration)},
          {"all_converged", totals.all_converged},
          {"wall_s", ExactJson(totals.wall_s)},
          {"step_us_count", totals.step_us.count()},
          {"model_steps", totals.model_steps},
          {"sleeping_body_steps", totals.sleeping_body_steps},
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
  // (nor one before sleeping islands its sleeping bodies)
  if (node.contains("sleeping_body_steps"))
    totals.sleeping_body_steps = node.at("sleeping_body_steps").get<long>();
  const Eigen::VectorXd sample =
      ReadExactVector(node.at("step_us_sample"), "totals.step_us_sample", -1);
  totals.step_us =
      ReservoirMedian(std::vector<double>(sample.data(), sample.data() + sample.size()),
                      node.at("step_us_count").get<std::int64_t>());
  return totals;
}

}  // namespace

void WriteCheckpoint(const std::string& path, const Checkpoint& checkpoint) {
  const json file = {
      {"format", kFormat},
      {"origin", checkpoint.origin},
      // readable, for people; the exact time is state.t
      {"t", checkpoint.state.t},
      {"rows", checkpoint.rows},
      {"totals", TotalsJson(checkpoint.totals)},
      {"state", engine::StateRecord(checkpoint.state)},
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
    checkpoint.state = engine::StateFromRecord(file.at("state"), "state");
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
