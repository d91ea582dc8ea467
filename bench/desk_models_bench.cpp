// Step time of the paper's desk (scenes/desk.yaml) with each contact model: planar sliding, hull
// ECP and multi-patch (the paper's table: 2.2 ms : 5.3 ms : 48.7 ms in MATLAB).

#include <string>

#include <benchmark/benchmark.h>

#include "engine/scene_yaml.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// the shipped scene with `model=<name>`, stepped over its 4 s and restarted; µs per step and
// mean Newton iterations per step
void BM_DeskModelStep(benchmark::State& bench, const std::string& model) {
  const Scene scene =
      LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/desk.yaml", {"model=" + model});
  const int steps = static_cast<int>(scene.duration / scene.h + 0.5);
  State state = InitialState(scene);
  long iterations = 0, count = 0;
  for (auto _ : bench) {
    if (count % steps == 0) state = InitialState(scene);
    iterations += Step(scene, state).iterations;
    ++count;
  }
  bench.counters["newton_iters"] = static_cast<double>(iterations) / count;
}
BENCHMARK_CAPTURE(BM_DeskModelStep, planar, std::string("planar"))
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DeskModelStep, hull, std::string("hull"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DeskModelStep, multipatch, std::string("multipatch"))
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ecpsim::engine
