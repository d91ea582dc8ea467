// Step-time benchmarks of contact islands (issue 13): what several bodies cost against one.
// The bars, read as ratios of medians of one run (README.md, "Islands"):
//   BM_IslandStack3 ≤ 4 × BM_IslandRestingBox (three boxes stacked against one box at rest);
//   BM_IslandScattered/64 ≤ 1.2 × 64 × BM_IslandRestingBox (each body an island of its own);
//   BM_IslandScatteredPairs/bodies:1024/every_pair:1 against …/every_pair:0: what a YAML
//   scene's default of every pair of bodies costs where none of them touches (issue 30);
//   BM_IslandGridPairs/bodies:1000/every_pair:1 against …/every_pair:0: the same with the
//   scaling benchmark's grid of stacks, sleeping (issue 30: cost linear in the bodies);
//   BM_IslandFreeFall: a body that can touch nothing costs the closed-form free flight;
//   BM_IslandSleep/<scene>/1 against BM_IslandSleep/<scene>/0: resting scenes with sleeping
//   islands on and off (engine/README.md, "Sleeping islands");
//   BM_IslandCrossedBars/parts:1 against …/parts:0: two bars of 20 parts each, one across the
//   other, where 4 pairs of parts touch, against the same bars touching with their hulls
//   (issue 31's bar for bodies made of parts: ≤ 5×);
//   BM_IslandThreads/<scene>/threads:2 against …/threads:1: scenes of many islands solved on
//   two threads against one, in wall time (the workers' CPU time is not the caller's);
//   BM_IslandTrain: scenes/train.yaml's push once the row moves (issue 30's bar: ≤ 100 µs).
// Every scene is stepped with the hull model, whose islands these are (model: auto would turn
// the single resting box into a planar step and the comparison into one of two models), and
// awake (solver.sleep false) but in BM_IslandSleep and BM_IslandGridPairs: they time the islands'
// solves, which sleeping would replace by replays of resting bodies.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "bench/step_loop.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_yaml.h"
#include "evaluation/stack_grid.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

constexpr int kRestartSteps = 500;  // 5 s at h = 0.01 s, then from t = 0 again

const Friction kFriction{0.5, 1, 1, 0.05};

Body RestingBox(const Vector3d& size, double mass, const Vector3d& at, const std::string& name) {
  Body box = testing::MakeBoxBody(size, mass, name);
  box.p0 = at;
  box.friction = kFriction;
  return box;
}

Scene HullScene(std::vector<Body> bodies) {
  Scene scene = testing::MakeGroundScene(std::move(bodies), 0.01, kFriction);
  AddBodyPairs(scene);
  scene.model = ContactModel::kHull;
  scene.solver.sleep = false;
  return scene;
}

// the counter "per_body": the time per step divided by the scene's bodies
void CountPerBody(benchmark::State& bench, const Scene& scene) {
  bench.counters["per_body"] =
      benchmark::Counter(static_cast<double>(bench.iterations()) * scene.bodies.size(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// steps `scene` (bench/step_loop.h), restarting from t = 0 every kRestartSteps steps; µs per
// step, and per body
void RunIslandSteps(benchmark::State& bench, const Scene& scene) {
  RunSteps(bench, scene, kRestartSteps);
  bench.counters["bodies"] = static_cast<double>(scene.bodies.size());
  CountPerBody(bench, scene);
}

// one 0.2 m box at rest on the ground: the unit of the other benchmarks
void BM_IslandRestingBox(benchmark::State& bench) {
  RunIslandSteps(bench, HullScene({RestingBox({0.2, 0.2, 0.1}, 1, {0, 0, 0.05}, "box")}));
}
BENCHMARK(BM_IslandRestingBox)->Unit(benchmark::kMicrosecond);

// three boxes stacked at rest, 0.3, 0.2 and 0.1 m wide, centred at (x, y) on the ground
void AddStack(double x, double y, const std::string& name, std::vector<Body>& boxes) {
  const double sizes[3] = {0.3, 0.2, 0.1};
  for (int i = 0; i < 3; ++i) {
    boxes.push_back(RestingBox({sizes[i], sizes[i], 0.1}, 3 - i, {x, y, 0.05 + 0.1 * i},
                               name + std::to_string(i)));
  }
}

// three boxes stacked at rest (tests/engine/body_contact_test.cpp's stack): one island of three
// bodies and three contacts
void BM_IslandStack3(benchmark::State& bench) {
  std::vector<Body> boxes;
  AddStack(0, 0, "box", boxes);
  RunIslandSteps(bench, HullScene(boxes));
}
BENCHMARK(BM_IslandStack3)->Unit(benchmark::kMicrosecond);

// a 4 × 4 grid of BM_IslandStack3's stack, 0.5 m apart: 48 bodies in 16 islands
Scene GridOfStacks() {
  std::vector<Body> boxes;
  for (int i = 0; i < 16; ++i)
    AddStack(0.5 * (i % 4), 0.5 * (i / 4), fmt::format("s{}_", i), boxes);
  return HullScene(boxes);
}

// n boxes at rest on a grid 0.5 m apart
std::vector<Body> ScatteredBoxes(int n) {
  const int side = static_cast<int>(std::ceil(std::sqrt(n)));
  std::vector<Body> boxes;
  for (int i = 0; i < n; ++i) {
    boxes.push_back(RestingBox({0.2, 0.2, 0.1}, 1, {0.5 * (i % side), 0.5 * (i / side), 0.05},
                               "box" + std::to_string(i)));
  }
  return boxes;
}

// the scattered boxes with every pair of them a contact pair, as a YAML scene without `pairs:`
// has them: n one-body islands, the broad phase over n(n−1)/2 pairs
void BM_IslandScattered(benchmark::State& bench) {
  RunIslandSteps(bench, HullScene(ScatteredBoxes(static_cast<int>(bench.range(0)))));
}
BENCHMARK(BM_IslandScattered)->Arg(8)->Arg(64)->Unit(benchmark::kMicrosecond);

// `scene` under the hull model stepped after `settle_steps` untimed steps, never restarted (at a
// thousand boxes a restart from t = 0 inside the timed loop would be most of what it times)
void RunSettledSteps(benchmark::State& bench, Scene& scene, int settle_steps) {
  scene.model = ContactModel::kHull;
  State state = InitialState(scene);
  StepWorkspace workspace;
  for (int k = 0; k < settle_steps; ++k) Step(scene, state, workspace);
  for (auto _ : bench) Step(scene, state, workspace);
  bench.counters["pairs"] = static_cast<double>(scene.contacts.size());
  CountPerBody(bench, scene);
}

// the scattered boxes at rest, stepped after 5 untimed steps, with every pair of
// bodies a contact pair (second argument 1) or none (0): what the pairs that never touch cost
// where a YAML scene lists none (each a ContactState in the state and a test in every step)
void BM_IslandScatteredPairs(benchmark::State& bench) {
  Scene scene =
      testing::MakeGroundScene(ScatteredBoxes(static_cast<int>(bench.range(0))), 0.01, kFriction);
  if (bench.range(1) == 1) AddBodyPairs(scene);
  scene.solver.sleep = false;
  RunSettledSteps(bench, scene, 5);
}
BENCHMARK(BM_IslandScatteredPairs)
    ->ArgNames({"bodies", "every_pair"})
    ->ArgsProduct({{64, 1024}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

// the scaling benchmark's grid of stacks at rest (evaluation/stack_grid.h) with the pairs within
// each stack (every_pair:0) or every pair of bodies (1), as a YAML scene lists them by default,
// sleeping as a user runs it: what a step pays for pairs the broad phase leaves out (500,500 of
// them at 1,000 bodies), stepped after 20 untimed steps (its islands asleep)
void BM_IslandGridPairs(benchmark::State& bench) {
  const int bodies = static_cast<int>(bench.range(0));
  Scene scene = evaluation::MakeStackGrid(bodies);
  if (bench.range(1) == 1) {
    // the ground's contacts (each body's, first) kept, then every pair (AddBodyPairs indexes)
    scene.contacts.resize(bodies);
    AddBodyPairs(scene);
  }
  RunSettledSteps(bench, scene, 20);
}
BENCHMARK(BM_IslandGridPairs)
    ->ArgNames({"bodies", "every_pair"})
    ->ArgsProduct({{64, 250, 1000}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

// a box falling from 200 m (122 m in the 5 s before each restart): every step is the
// closed-form free flight
void BM_IslandFreeFall(benchmark::State& bench) {
  RunIslandSteps(bench, HullScene({RestingBox({0.2, 0.2, 0.1}, 1, {0, 0, 200}, "box")}));
}
BENCHMARK(BM_IslandFreeFall)->Unit(benchmark::kMicrosecond);

// resting scenes stepped from 0.5 s on, once at rest, with sleeping on (second argument 1) and
// off (0): scenes/stack.yaml (0), scenes/pyramid.yaml (1), and GridOfStacks (2)
void BM_IslandSleep(benchmark::State& bench) {
  Scene scene;
  if (bench.range(0) == 2) {
    scene = GridOfStacks();
  } else {
    const char* file = bench.range(0) == 0 ? "/scenes/stack.yaml" : "/scenes/pyramid.yaml";
    scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + file).scene;
  }
  scene.solver.sleep = bench.range(1) == 1;
  State state = InitialState(scene);
  StepWorkspace workspace;
  constexpr int kSettleSteps = 50;
  for (int k = 0; k < kSettleSteps; ++k) Step(scene, state, workspace);
  long sleeping = 0, count = 0;
  for (auto _ : bench) {
    sleeping += Step(scene, state, workspace).sleeping_bodies;
    ++count;
  }
  bench.counters["sleeping"] = static_cast<double>(sleeping) / (count * scene.bodies.size());
}
BENCHMARK(BM_IslandSleep)
    ->ArgNames({"scene", "sleep"})
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

// scenes/train.yaml's push once the row moves at the pusher's speed: its steps from 0.5 s to
// the scene's end at 2 s, again and again (the state at 0.5 s restored every 150 steps): one
// island of six boxes pushing each other and sliding on the ground (issue 30's bar: ≤ 100 µs)
void BM_IslandTrain(benchmark::State& bench) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/train.yaml").scene;
  State settled = InitialState(scene);
  StepWorkspace workspace;
  constexpr int kSettleSteps = 50, kTrainRestartSteps = 150;
  for (int k = 0; k < kSettleSteps; ++k) Step(scene, settled, workspace);
  State state = settled;
  long iterations = 0, count = 0;
  for (auto _ : bench) {
    if (count % kTrainRestartSteps == 0) state = settled;
    iterations += Step(scene, state, workspace).iterations;
    ++count;
  }
  bench.counters["newton_iters"] = static_cast<double>(iterations) / count;
}
BENCHMARK(BM_IslandTrain)->Unit(benchmark::kMicrosecond);

// scenes of many islands, awake, solved on `threads` threads (second argument): the 64
// scattered boxes (0: 64 islands of one body) and the grid of stacks (1: 16 islands of three)
void BM_IslandThreads(benchmark::State& bench) {
  const Scene scene = bench.range(0) == 0 ? HullScene(ScatteredBoxes(64)) : GridOfStacks();
  RunSteps(bench, scene, kRestartSteps, static_cast<int>(bench.range(1)));
  CountPerBody(bench, scene);
}
BENCHMARK(BM_IslandThreads)
    ->ArgNames({"scene", "threads"})
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// two bars of 20 box parts each, 0.4 m long, one along x on the ground and one along y across it,
// 3 and 3.7 mm off the other's centre lines: 400 pairs of parts, of which the 2 × 2 at the
// crossing touch. The parts are 2 cm long and overlap their neighbours by 2 mm each way, so no
// seam between two parts lies on a bar's surface (docs/scene_format.md, "Decomposition")
std::string CrossedBarsYaml(bool parts) {
  constexpr int kParts = 20;
  constexpr double kLength = 0.4, kPitch = kLength / kParts, kOverlap = 0.002;
  std::string yaml =
      "duration: 5\nh: 0.01\nmodel: hull\nsolver: {sleep: false}\n"
      "ground: {friction: {mu: 0.5, e_r: 0.05}}\n"
      "bodies:\n";
  for (const int axis : {0, 1}) {
    yaml += fmt::format(
        "  - name: bar{}\n    shape: {{box: {{size: [{}, {}, 0.02]}}}}\n    mass: 0.1\n"
        "    position: [{}, {}, {}]\n    decomposition: {}\n    parts:\n",
        axis, axis == 0 ? kLength : 0.02, axis == 0 ? 0.02 : kLength, axis == 0 ? 0.0 : 0.003,
        axis == 0 ? 0.0 : 0.0037, axis == 0 ? 0.01 : 0.03, parts ? "parts" : "none");
    for (int i = 0; i < kParts; ++i) {
      const double lo = std::max(-kLength / 2, -kLength / 2 + kPitch * i - kOverlap);
      const double hi = std::min(kLength / 2, -kLength / 2 + kPitch * (i + 1) + kOverlap);
      const double at = 0.5 * (lo + hi), length = hi - lo;
      yaml += fmt::format("      - {{box: {{size: [{}, {}, 0.02]}}, at: [{}, {}, 0]}}\n",
                          axis == 0 ? length : 0.02, axis == 0 ? 0.02 : length,
                          axis == 0 ? at : 0.0, axis == 0 ? 0.0 : at);
    }
  }
  return yaml;
}

void BM_IslandCrossedBars(benchmark::State& bench) {
  const Scene scene =
      LoadSceneText(CrossedBarsYaml(bench.range(0) == 1), "crossed_bars.yaml", ".").scene;
  RunIslandSteps(bench, scene);
  bench.counters["contacts"] = static_cast<double>(scene.contacts.size());
}
BENCHMARK(BM_IslandCrossedBars)->ArgName("parts")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ecpsim::engine
