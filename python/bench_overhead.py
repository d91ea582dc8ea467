"""What stepping from a Python loop costs over the same steps in C++ (issue 12: at most 1 µs
more per step).

    PYTHONPATH=build/python python3 python/bench_overhead.py [scene.yaml] [--steps N]

The C++ loop is Simulation.step(N): one call, N engine steps in C++. The Python loop is N calls
of Simulation.step(), and a control loop also reads the positions and applies a wrench each step
(the closed loop of examples/). Each is timed on the same states (reset before every repeat); the
median of the repeats is printed per step, side by side, with the difference.
"""

import argparse
import pathlib
import statistics
import time

import ecpsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


def per_step_us(sim, steps, repeats, loop):
    """Median over repeats of the wall time per step, µs."""
    times = []
    for _ in range(repeats):
        sim.reset()
        start = time.perf_counter()
        loop(sim, steps)
        times.append((time.perf_counter() - start) / steps * 1e6)
    return statistics.median(times)


def cpp_loop(sim, steps):
    sim.step(steps)


def python_loop(sim, steps):
    step = sim.step
    for _ in range(steps):
        step()


def control_loop(sim, steps):
    for _ in range(steps):
        x = sim.positions[0]
        sim.apply_wrench(0, force=(0.0, 0.0, 0.0 * x[0]))
        sim.step()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=str(ROOT / "scenes" / "slide.yaml"))
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()

    scene = ecpsim.load_scene(args.scene, {"duration": 1e3})
    sim = ecpsim.Simulation(scene)
    cpp = per_step_us(sim, args.steps, args.repeats, cpp_loop)
    python = per_step_us(sim, args.steps, args.repeats, python_loop)
    control = per_step_us(sim, args.steps, args.repeats, control_loop)
    print(f"scene {args.scene}: {args.steps} steps, median of {args.repeats} repeats")
    print(f"  C++ loop     step(N)                  {cpp:9.3f} us/step")
    print(f"  Python loop  step() N times           {python:9.3f} us/step  "
          f"(+{python - cpp:.3f} us)")
    print(f"  Python loop  positions, apply_wrench, step()  {control:9.3f} us/step  "
          f"(+{control - cpp:.3f} us)")


if __name__ == "__main__":
    main()
