#pragma once
// The benchmarks' step loop: a scene stepped from t = 0, restarted every `restart_steps` steps,
// one step per benchmark iteration (Google Benchmark's time per iteration is the step's).

#include <benchmark/benchmark.h>

#include "engine/island_threads.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {

/// Steps `scene` once per iteration of `bench`, from its initial state again every
/// `restart_steps` steps; sets the counter "newton_iters", the mean solver iterations per step
/// (Lemke pivots for the point model). The islands are solved on `threads` threads.
inline void RunSteps(benchmark::State& bench, const Scene& scene, int restart_steps,
                     int threads = 1) {
  State state = InitialState(scene);
  StepWorkspace workspace;
  IslandThreadsOf(workspace).SetThreads(threads);
  long iterations = 0, count = 0;
  for (auto _ : bench) {
    if (count % restart_steps == 0) state = InitialState(scene);
    iterations += Step(scene, state, workspace).iterations;
    ++count;
  }
  bench.counters["newton_iters"] = static_cast<double>(iterations) / count;
}

}  // namespace ecpsim::engine
