// Step time of the paper's desk (scenes/desk.yaml) with each contact model: planar sliding, hull
// ECP and multi-patch (the paper's table: 2.2 ms : 5.3 ms : 48.7 ms in MATLAB).

#include <string>

#include <benchmark/benchmark.h>

#include "bench/step_loop.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// the shipped scene with `model=<name>`, stepped over its 4 s and restarted; µs per step and
// mean Newton iterations per step
void BM_DeskModelStep(benchmark::State& bench, const std::string& model) {
  const Scene scene =
      LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/desk.yaml", {"model=" + model}).scene;
  RunSteps(bench, scene, static_cast<int>(scene.duration / scene.h + 0.5));
}
BENCHMARK_CAPTURE(BM_DeskModelStep, planar, std::string("planar"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DeskModelStep, hull, std::string("hull"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DeskModelStep, multipatch, std::string("multipatch"))
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ecpsim::engine
