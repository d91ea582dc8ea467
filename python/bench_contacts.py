"""What reading the contacts costs from Python: contacts() as dicts against contacts(as_arrays=True)
and a kinematic body's sensor(), per call.

    PYTHONPATH=build/python python3 python/bench_contacts.py [--steps N] [--calls N]

Each scene is stepped N steps first (so that its contacts carry impulses), then each reading is
called repeatedly; the median over repeats of the time per call is printed.
"""

import argparse
import pathlib
import statistics
import timeit

import ecpsim

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENES = ["push_box.yaml", "dominoes.yaml"]


def per_call_us(call, calls, repeats):
    """Median over repeats of the time per call, µs."""
    return statistics.median(timeit.repeat(call, number=calls, repeat=repeats)) / calls * 1e6


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=60)
    parser.add_argument("--calls", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    for name in SCENES:
        sim = ecpsim.Simulation(ecpsim.load_scene(str(ROOT / "scenes" / name)))
        sim.step(args.steps)
        dicts = per_call_us(sim.contacts, args.calls, args.repeats)
        arrays = per_call_us(lambda: sim.contacts(as_arrays=True), args.calls, args.repeats)
        print(f"{name}: {len(sim.scene.contact_names)} contacts, median of {args.repeats} repeats")
        print(f"  contacts()                {dicts:8.2f} us/call")
        print(f"  contacts(as_arrays=True)  {arrays:8.2f} us/call")
        kinematic = [b["name"] for b in sim.scene.bodies if b["kinematic"]]
        if kinematic:
            sensor = per_call_us(lambda: sim.sensor(kinematic[0]), args.calls, args.repeats)
            print(f"  sensor('{kinematic[0]}')       {sensor:8.2f} us/call")


if __name__ == "__main__":
    main()
