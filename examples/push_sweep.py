"""A Monte Carlo sweep of a push on a Dask cluster: a finger pushes a standing box
(examples/push_sweep.yaml) with random ground friction μ and torsion e_r, push point and speed;
each run's outcome becomes a row of a table (CSV) and the distribution a plot.

    PYTHONPATH=build/python /usr/bin/python3 examples/push_sweep.py [-o out/push_sweep]
        [--runs 1000] [--seed 1] [--duration 1] [--workers 2] [--threads | --serial]
        [--scheduler tcp://host:8786] [--scene examples/push_sweep.yaml]

By default a LocalCluster of --workers processes with one thread each; --threads runs the
workers as threads of this process instead (Simulation.step releases the GIL, the Python loop
around it does not: threads measured about a second per sweep faster on one machine,
docs/python.md); --scheduler uses an existing cluster (`dask scheduler`, `dask worker`):
every worker must import ecpsim (PYTHONPATH or cmake --install) and read the scene file at the
path given here (a shared or identical checkout). A run's outcome depends on its case only, so
the table is the same for any cluster and equal to a serial run (tests/python/
test_push_sweep.py checks both, and a fixed seed giving the same table).

Cases: run i draws from numpy's default_rng([seed, i]), so the first k runs are the same for any
--runs ≥ k: μ ∈ [0.1, 0.7] and e_r ∈ [0.01, 0.1] m (the box–ground contact; the finger–box pair
takes μ = sqrt(0.5 μ)), the push point y ∈ [−0.08, 0.08] m across the 0.2 m face and height
z ∈ [0.02, 0.18] m, the finger's speed ∈ [0.05, 0.3] m/s; 1 s at h = 0.01 s.

push_sweep.csv, one row per run in case order (a run whose step failed keeps its case columns,
leaves the outcome columns empty and names the failure; the sweep goes on):
  case            index of the run
  mu, e_r         ground friction: Coulomb coefficient, torsion semi-axis (m)
  push_y, push_z  m: the finger's axis across the face (0: through the CM) and its height
  speed           m/s, the finger's velocity along +x
  x, y, z         m, the box's CM at the end
  qw, qx, qy, qz  its orientation at the end (body → world)
  displacement    m, horizontal distance its CM moved
  rotation        rad, the turn of its y axis (along the pushed face) about the vertical
                  (positive counter-clockwise; well defined also when it tipped forward)
  max_tilt        rad, the largest angle of its z axis from the vertical
  slid            1 if the box–ground contact slid in some step, else 0
  tipped          1 if max_tilt passed atan(b/H) = 26.6° (its CM beyond the bottom edge)
  sensor_fx, sensor_fy, sensor_fz
                  N, what a force sensor on the finger read in the last step (world axes): the
                  force of the box on it (a steady push: −μ m g along x)
  sensor_peak     N, the largest magnitude the sensor read in any step
  failure         empty, or the solver's message (time, body, residual)
push_sweep.png: the box's rotation against the push point, coloured by μ; and the push height
against μ, tipped or not, with the statics' boundary μ z = b/2.
"""

import argparse
import csv
import io
import math
import pathlib
import sys

import numpy as np

import ecpsim
from atomic_output import save_figure_atomically, write_bytes_atomically
from dask_cluster import add_cluster_options, cluster_client

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "push_sweep.yaml"
BOX_DEPTH, BOX_HEIGHT = 0.1, 0.2      # m, as push_sweep.yaml
FINGER_START_X = -0.07                # m, as push_sweep.yaml: 1 cm behind the box
TIP_ANGLE = math.atan(BOX_DEPTH / BOX_HEIGHT)  # rad: the CM over the bottom edge

# the ranges of the random parameters (module docstring)
RANGES = {"mu": (0.1, 0.7), "e_r": (0.01, 0.1), "push_y": (-0.08, 0.08), "push_z": (0.02, 0.18),
          "speed": (0.05, 0.3)}
CASE_COLUMNS = ["case", "mu", "e_r", "push_y", "push_z", "speed"]
OUTCOME_COLUMNS = ["x", "y", "z", "qw", "qx", "qy", "qz", "displacement", "rotation", "max_tilt",
                   "slid", "tipped", "sensor_fx", "sensor_fy", "sensor_fz", "sensor_peak"]
COLUMNS = CASE_COLUMNS + OUTCOME_COLUMNS + ["failure"]


def make_case(index, mu, e_r, push_y, push_z, speed, duration=1.0, scene=SCENE):
    """One push (a plain dict, which pickles to any worker): the CASE_COLUMNS, the run's
    duration (s) and the base scene's path."""
    return {"case": index, "mu": mu, "e_r": e_r, "push_y": push_y, "push_z": push_z,
            "speed": speed, "duration": duration, "scene": str(scene)}


def make_cases(runs, seed, duration=1.0, scene=SCENE):
    """`runs` random cases; case i is drawn from default_rng([seed, i]) alone."""
    cases = []
    for i in range(runs):
        rng = np.random.default_rng([seed, i])
        values = {name: float(rng.uniform(low, high)) for name, (low, high) in RANGES.items()}
        cases.append(make_case(i, duration=duration, scene=scene, **values))
    return cases


def push_scene(case):
    """The base scene with the case's --set overrides."""
    return ecpsim.load_scene(case["scene"], {
        "duration": case["duration"],
        "ground.friction.mu": case["mu"],
        "ground.friction.e_r": case["e_r"],
        "bodies.1.motion.velocity.position": [FINGER_START_X, case["push_y"], case["push_z"]],
        "bodies.1.motion.velocity.linear": [case["speed"], 0.0, 0.0],
    })


def rotation_about_vertical(q):
    """rad: the heading of the body's y axis in the horizontal plane, from world y."""
    w, x, y, z = q
    return math.atan2(-2 * (x * y - w * z), 1 - 2 * (x * x + z * z))


def tilt(q):
    """rad: the angle of the body's z axis from the vertical."""
    w, x, y, z = q
    return math.acos(min(1.0, max(-1.0, 1 - 2 * (x * x + y * y))))


def simulate_push(case):
    """One run of `case`: a dict of COLUMNS (outcome None and `failure` the message if a step
    failed). Deterministic: the same case gives the same doubles on any machine of this build."""
    row = {name: case[name] for name in CASE_COLUMNS}
    row["failure"] = ""
    scene = push_scene(case)
    sim = ecpsim.Simulation(scene)
    contact = {c: k for k, c in enumerate(scene.contact_names)}
    ground, push = contact["box.ground"], contact["box.finger"]
    p0 = sim.positions[0]
    slid, max_tilt, peak = False, 0.0, 0.0
    try:
        for _ in range(int(round(scene.duration / scene.h))):
            sim.step()
            contacts = sim.contacts()
            slid |= contacts[ground]["mode"] == "sliding"
            sensor = -contacts[push]["force"]  # on the finger, from the box
            peak = max(peak, float(np.linalg.norm(sensor)))
            max_tilt = max(max_tilt, tilt(sim.quaternions[0]))
    except ecpsim.SolverFailure as failure:
        row.update({name: None for name in OUTCOME_COLUMNS}, failure=str(failure))
        return row
    p, q = sim.positions[0], sim.quaternions[0]
    row.update(x=p[0], y=p[1], z=p[2], qw=q[0], qx=q[1], qy=q[2], qz=q[3],
               displacement=math.hypot(p[0] - p0[0], p[1] - p0[1]),
               rotation=rotation_about_vertical(q), max_tilt=max_tilt,
               slid=int(slid), tipped=int(max_tilt > TIP_ANGLE),
               sensor_fx=sensor[0], sensor_fy=sensor[1], sensor_fz=sensor[2], sensor_peak=peak)
    return {name: float(v) if isinstance(v, np.floating) else v for name, v in row.items()}


def run_sweep(cases, client=None):
    """The rows of `cases` in case order: on the Dask `client`'s cluster, or here, one after
    another, when it is None."""
    if client is None:
        return [simulate_push(case) for case in cases]
    return client.gather(client.map(simulate_push, cases))


def table(rows):
    """CSV text of `rows` with COLUMNS (floats as Python's shortest round-trip repr)."""
    text = io.StringIO()
    writer = csv.DictWriter(text, COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return text.getvalue()


def read_table(path):
    """push_sweep.csv back as rows: numbers as float (case, slid, tipped as int), None where
    empty, the failure as text."""
    def value(name, text):
        if name == "failure":
            return text
        if text == "":
            return None
        return int(text) if name in ("case", "slid", "tipped") else float(text)
    with open(path, newline="") as file:
        return [{k: value(k, v) for k, v in row.items()} for row in csv.DictReader(file)]


def plot(rows, path):
    """The outcome distribution as a PNG at `path` (atomically)."""
    from matplotlib.figure import Figure  # no pyplot: no GUI backend

    done = [r for r in rows if not r["failure"]]
    failed = [r for r in rows if r["failure"]]
    figure = Figure(figsize=(11, 4.5), layout="constrained")
    turn, tip = figure.subplots(1, 2)
    for tipped, marker in ((0, "o"), (1, "x")):
        part = [r for r in done if r["tipped"] == tipped]
        points = turn.scatter([r["push_y"] * 1e3 for r in part],
                              [math.degrees(r["rotation"]) for r in part],
                              c=[r["mu"] for r in part], cmap="viridis", vmin=RANGES["mu"][0],
                              vmax=RANGES["mu"][1], marker=marker, s=12,
                              label="tipped" if tipped else "slid or rested")
    figure.colorbar(points, ax=turn, label="ground μ")
    turn.set_xlabel("push point y (mm from the CM line)")
    turn.set_ylabel("box rotation about z (°)")
    turn.legend(loc="upper right")
    for label, part, style in (("slid or rested", [r for r in done if not r["tipped"]], "o"),
                               ("tipped", [r for r in done if r["tipped"]], "x"),
                               ("solver failure", failed, "s")):
        tip.scatter([r["mu"] for r in part], [r["push_z"] * 1e3 for r in part], marker=style,
                    s=12, label=f"{label} ({len(part)})")
    mu = np.linspace(*RANGES["mu"], 100)
    tip.plot(mu, np.minimum(BOX_DEPTH / 2 / mu, BOX_HEIGHT) * 1e3, "k--", lw=1,
             label="statics: μ z = b/2")
    tip.set_xlabel("ground μ")
    tip.set_ylabel("push height z (mm)")
    tip.set_ylim(0, RANGES["push_z"][1] * 1e3 * 1.05)
    tip.legend(loc="upper right", fontsize="small")
    figure.suptitle(f"{len(rows)} pushes of a standing box by a finger")
    return save_figure_atomically(figure, path)


def summary(rows):
    """One line: how many runs slid, tipped and failed."""
    done = [r for r in rows if not r["failure"]]
    return (f"{len(rows)} runs: {sum(r['slid'] for r in done)} slid, "
            f"{sum(r['tipped'] for r in done)} tipped, {len(rows) - len(done)} solver failures")


def main(argv=None):
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("-o", "--output", default="out/push_sweep", help="output folder")
    parser.add_argument("--runs", type=int, default=1000, help="number of pushes")
    parser.add_argument("--seed", type=int, default=1, help="case i draws from [seed, i]")
    parser.add_argument("--duration", type=float, default=1.0, help="s per run")
    add_cluster_options(parser, threads=True)
    parser.add_argument("--serial", action="store_true", help="no Dask: every run here")
    parser.add_argument("--scene", default=str(SCENE), help="the base scene")
    args = parser.parse_args(argv)
    if args.runs < 1 or args.workers < 1:
        print(f"error: --runs = {args.runs}, --workers = {args.workers}: expected ≥ 1",
              file=sys.stderr)
        return 1
    cases = make_cases(args.runs, args.seed, args.duration, pathlib.Path(args.scene).resolve())
    try:
        push_scene(cases[0])  # bad scene or overrides: an error here, before any cluster
    except ecpsim.InputError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    if args.serial:
        rows = run_sweep(cases)
    else:
        with cluster_client(args.scheduler, args.workers, args.threads) as client:
            rows = run_sweep(cases, client)
    out = pathlib.Path(args.output)
    csv_path = write_bytes_atomically(out / "push_sweep.csv", table(rows).encode())
    png_path = plot(rows, out / "push_sweep.png")
    print(f"{summary(rows)}; wrote {csv_path} and {png_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
