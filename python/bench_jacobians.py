"""What step_jacobians() costs against a step and against central differences of whole steps.

    PYTHONPATH=build/python python3 python/bench_jacobians.py [--calls N] [--repeats N]

At the states tests/python/test_step_jacobians.py linearizes (each scene stepped to where its
test takes it), times one step (from a saved state, restored before each), one
step_jacobians() and one set of central differences of whole steps from Python (2 steps per
state coordinate and input: 36 per dynamic body, each from a restored state); prints the
medians over repeats per call.
"""

import argparse
import pathlib
import statistics
import timeit

import ecpsim

ROOT = pathlib.Path(__file__).resolve().parents[1]
# scene and the steps taken before linearizing, as in the test
STATES = [("slide.yaml", 5), ("tilted_box.yaml", 10), ("desk.yaml", 20), ("push_box.yaml", 40),
          ("gripper.yaml", 80)]


def per_call_us(call, calls, repeats):
    """Median over repeats of the time per call, µs."""
    return statistics.median(timeit.repeat(call, number=calls, repeat=repeats)) / calls * 1e6


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    print(f"median of {args.repeats} repeats of {args.calls} calls, µs per call")
    print(f"{'scene':18s} {'step':>10s} {'step_jacobians':>15s} {'ratio':>7s} "
          f"{'central differences':>20s}")
    for name, steps in STATES:
        sim = ecpsim.Simulation(ecpsim.load_scene(str(ROOT / "scenes" / name)))
        sim.step(steps)
        saved = sim.get_state()
        dynamic = len(sim.step_jacobians().bodies)

        def one_step():
            sim.set_state(saved)
            sim.step()

        def differences():
            # 2 × (12 + 6) whole steps per dynamic body, each from the saved state
            for _ in range(36 * dynamic):
                one_step()

        step = per_call_us(one_step, args.calls, args.repeats)
        sim.set_state(saved)
        jacobians = per_call_us(sim.step_jacobians, args.calls, args.repeats)
        central = per_call_us(differences, max(1, args.calls // 10), args.repeats)
        print(f"{name:18s} {step:10.1f} {jacobians:15.1f} {jacobians / step:6.1f}x "
              f"{central:20.1f}")


if __name__ == "__main__":
    main()
