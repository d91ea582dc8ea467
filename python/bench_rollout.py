"""Batched rollouts on threads against one thread (issue 32 item 4: at least 1.8× on 2 threads).

    PYTHONPATH=build/python python3 python/bench_rollout.py [scene.yaml] [--sims 8]
        [--steps 4000] [--threads 1 2] [--repeats 7] [--set KEY=VALUE ...]

Times ecpsim.rollout of `--sims` Simulations of the scene (default the desk: its loads push and
twist it the whole time, so every step solves its four-leg contact, by the planar model under
the scene's `model: auto`; `--set model=hull` solves the hull MNCP instead, a few times dearer)
for N steps each, once per thread count and repeat (--set: load_scene overrides, as the CLI's);
every repeat starts from fresh Simulations at t = 0, so each thread count steps the same states. Prints the median wall time per thread count, its spread (min … max), the steps per
second, the speedup over the first thread count and the median CPU time of the process (on a busy
machine, CPU time near threads × wall time says the threads ran side by side, and CPU time above
the one thread's says what they cost each other), and checks that every thread count gave the
same arrays to the bit.
"""

import argparse
import os
import pathlib
import statistics
import time

import numpy as np

import ecpsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


def time_rollout(scene, sims, steps, threads):
    """Wall and CPU time (the process's, all threads) of one rollout of fresh Simulations, s,
    and its result."""
    batch = [ecpsim.Simulation(scene) for _ in range(sims)]
    start, start_cpu = time.perf_counter(), time.process_time()
    result = ecpsim.rollout(batch, steps, threads=threads)
    return time.perf_counter() - start, time.process_time() - start_cpu, result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=str(ROOT / "scenes" / "desk.yaml"))
    parser.add_argument("--sims", type=int, default=8)
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args()

    # a duration past the steps (the loads are expressions of t; run()'s duration is unused)
    scene = ecpsim.load_scene(args.scene, ["duration=1e3"] + args.set)
    times = {threads: [] for threads in args.threads}
    cpu = {threads: [] for threads in args.threads}
    results = {}
    # the thread counts interleaved, so that a change of the machine's load meets all of them
    for _ in range(args.repeats):
        for threads in args.threads:
            seconds, cpu_seconds, results[threads] = time_rollout(scene, args.sims, args.steps,
                                                                  threads)
            times[threads].append(seconds)
            cpu[threads].append(cpu_seconds)
    first = args.threads[0]
    for threads in args.threads[1:]:
        for key, value in results[first].items():
            if not np.array_equal(value, results[threads][key]):
                raise SystemExit(f"threads={threads}: {key} differs from threads={first}")

    load = os.getloadavg()
    print(f"scene {args.scene} {' '.join(args.set)}: {args.sims} simulations × {args.steps} steps, median of "
          f"{args.repeats} repeats (load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}, "
          f"{os.cpu_count()} CPUs)")
    base = statistics.median(times[first])
    for threads in args.threads:
        median = statistics.median(times[threads])
        steps_per_s = args.sims * args.steps / median
        print(f"  threads={threads}: {median:8.3f} s  ({min(times[threads]):.3f} … "
              f"{max(times[threads]):.3f})  {steps_per_s:9.0f} steps/s  "
              f"speedup {base / median:.2f}×  CPU {statistics.median(cpu[threads]):.3f} s")
    print("  the arrays of every thread count are identical")


if __name__ == "__main__":
    main()
