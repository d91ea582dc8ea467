#include "tests/engine/trajectory_hash.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/time_step.h"

namespace ecpsim::engine::testing {
namespace {

constexpr std::array<ContactModel, 5> kModels = {ContactModel::kAuto, ContactModel::kHull,
                                                 ContactModel::kPlanar, ContactModel::kMultiPatch,
                                                 ContactModel::kPoint};

// steps of every case: 1.5 s at the usual h = 0.01 s, past the drops' landings, the paper
// scenes' first mode changes and the gripper's squeeze
constexpr int kDefaultSteps = 150;
// scenes whose later steps cost seconds each run fewer: the dominoes' 100 steps (0.5 s) hold the
// first collisions between blocks (d1 meets d2 at 0.15 s, d2 meets d3 at 0.26 s) and stop before
// the pile's landing, whose steps take minutes of CPU. The many-body scenes run under every model
// too, and the point model's Lemke solve sets their length: the pyramid's 5 steps (0.2 s of CPU
// each under the point model; its 16th takes minutes) hold the cold first step of its 15
// contacts and four of the rest that follows; the train's 10 (0.1 s each under the point model)
// hold the pusher's strike and the row's first steps at its speed (the force is μ Σ m g from the
// second step on). The hull and auto models' first step costs 1.1 s on the pyramid and 4.4 s on
// the train, their later steps 0.01–0.05 s; the planar and multi-patch models stop at the first
// step (boxes touch boxes).
const std::map<std::string, int>& ShortenedScenes() {
  static const std::map<std::string, int> steps = {
      {"dominoes.yaml", 100}, {"pyramid.yaml", 5}, {"train.yaml", 10}};
  return steps;
}

// FNV-1a over the bytes of the values fed in, so one flipped bit anywhere changes the hash
class StateHash {
 public:
  void Add(double x) { AddBytes(&x, sizeof x); }
  void Add(std::int64_t x) { AddBytes(&x, sizeof x); }
  void Add(const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) Add(v[i]);
  }
  void Add(const Eigen::Quaterniond& q) {
    for (int i = 0; i < 4; ++i) Add(q.coeffs()[i]);
  }
  std::uint64_t value() const { return hash_; }

 private:
  void AddBytes(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

ContactModel ModelNamed(const std::string& name) {
  for (ContactModel model : kModels) {
    if (name == ContactModelName(model)) return model;
  }
  throw InputError(fmt::format("trajectory hash: unknown model '{}'", name));
}

}  // namespace

std::vector<TrajectoryCase> AllTrajectoryCases(const std::string& scenes_dir) {
  std::vector<std::string> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(scenes_dir)) {
    if (entry.path().extension() == ".yaml") scenes.push_back(entry.path().filename().string());
  }
  std::sort(scenes.begin(), scenes.end());
  std::vector<TrajectoryCase> cases;
  for (const std::string& scene : scenes) {
    for (ContactModel model : kModels) cases.push_back({scene, ContactModelName(model)});
  }
  return cases;
}

std::uint64_t HashStep(const State& state, const StepReport& report) {
  StateHash hash;
  hash.Add(state.t);
  hash.Add(state.steps);
  for (const BodyState& body : state.bodies) {
    hash.Add(body.p_WB);
    hash.Add(body.Q_WB);
    hash.Add(body.v_WB);
    hash.Add(body.w_WB);
  }
  for (const ContactState& contact : state.contacts) {
    hash.Add(contact.a1);
    hash.Add(contact.a2);
    for (double x : {contact.p_n, contact.p_t, contact.p_o, contact.p_r, contact.sigma}) {
      hash.Add(x);
    }
    hash.Add(contact.n);
    hash.Add(contact.t);
    hash.Add(contact.o);
  }
  hash.Add(std::int64_t{report.converged});
  for (int count : {report.iterations, report.retries, report.substeps}) {
    hash.Add(std::int64_t{count});
  }
  hash.Add(report.residual);
  for (StepModel model : report.models) hash.Add(static_cast<std::int64_t>(model));
  return hash.value();
}

int TrajectoryHashSteps(const std::string& scene) {
  const auto shortened = ShortenedScenes().find(scene);
  return shortened == ShortenedScenes().end() ? kDefaultSteps : shortened->second;
}

std::vector<std::string> TrajectoryRecord(const std::string& scenes_dir,
                                          const TrajectoryCase& trajectory_case) {
  Scene scene = LoadScene(scenes_dir + "/" + trajectory_case.scene).scene;
  scene.model = ModelNamed(trajectory_case.model);
  State state = InitialState(scene);
  StepWorkspace workspace;
  const std::string prefix = trajectory_case.scene + " " + trajectory_case.model;
  std::vector<std::string> lines;
  const int steps = TrajectoryHashSteps(trajectory_case.scene);
  for (int i = 1; i <= steps; ++i) {
    try {
      const StepReport report = Step(scene, state, workspace);
      lines.push_back(fmt::format("{} {} {:016x}", prefix, i, HashStep(state, report)));
    } catch (const ModelInvalid&) {
      lines.push_back(fmt::format("{} end ModelInvalid at step {}", prefix, i));
      return lines;
    } catch (const SolverFailure&) {
      lines.push_back(fmt::format("{} end SolverFailure at step {}", prefix, i));
      return lines;
    }
  }
  lines.push_back(prefix + " end completed");
  return lines;
}

}  // namespace ecpsim::engine::testing
