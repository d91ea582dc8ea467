"""Where a grasp starts to slip, against Coulomb's prediction: scenes/gripper.yaml's jaws hold its
box (0.2 kg) with μ = 0.5 pads under `solver.selection: least_energy`, lift it 5 mm, then let
their closing force F fall slowly until the box slips or turns out of the grip.

    PYTHONPATH=build/python /usr/bin/python3 examples/grasp_slip.py [-o out/grasp_slip]
        [--figure docs/figures/grasp_slip_onset.png]

Cases: two pad sizes (4 × 3 cm and 2 × 1.5 cm across × along the lift) gripping at offsets d of
0 to 12.5 mm beside the box's CM. Each pad carries half the weight along the lift and half its
moment about the pad's normal, m g c / 2 with c the offset of the centroid of the pad's overlap
with the box's 5 cm face; on the pads' friction ellipsoid (f / μF)² + (τ / (e_r μF))² = 1
(e_r = 0.01 m) slip begins where

    2 μ F = m g √(1 + (c / e_r)²).

The force starts at 1.15 × that and falls by half of it per second from t = 1 s, so one 10 ms step
changes it by 0.58 % of the prediction; a step after which the box moved or turned relative to the
jaws by more than 1e-9 (m, rad) slipped, and the step before it held. tests/engine/grasp_test.cpp
asserts the bracket on five of these cases.

grasp_slip.csv, one row per case:
  pad_across, pad_along  m
  offset                 m, d: the grip's centre beside the CM
  centroid               m, c
  predicted              2 μ F / m g where slip begins (the formula above)
  held, slipped          2 μ F / m g of the last step that held and of the first that slipped
  turn                   rad, the box's turn relative to the jaws after the first slipping step
grasp_slip_onset.png: held and slipped against d, with the prediction per pad.
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

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "gripper.yaml"
MASS, G, MU, E_R = 0.2, 9.8, 0.5, 0.01  # kg, m/s², the pads' μ and e_r (m)
BOX_HALF_WIDTH = 0.025                   # m
PADS = [(0.04, 0.03), (0.02, 0.015)]     # m, across × along the lift
OFFSETS = [0.0, 0.0025, 0.005, 0.0075, 0.01, 0.0125]  # m
RAMP_START, RAMP_FROM, RAMP_RATE = 1.15, 1.0, 0.5  # × the prediction, s, prediction per s
HELD = 1e-9  # m and rad: a held box moves with the jaws to the solver's tolerance
COLUMNS = ["pad_across", "pad_along", "offset", "centroid", "predicted", "held", "slipped", "turn"]


def centroid(pad_across, offset):
    """m: the offset from the CM of the centroid of the pad's overlap with the box's face."""
    low = max(offset - pad_across / 2, -BOX_HALF_WIDTH)
    high = min(offset + pad_across / 2, BOX_HALF_WIDTH)
    return (low + high) / 2


def predicted_ratio(pad_across, offset):
    """2 μ F / m g where slip begins."""
    return math.hypot(1.0, centroid(pad_across, offset) / E_R)


def grasp_scene(pad_across, pad_along, offset):
    """The gripper scene with the case's pads, grip and force ramp."""
    force = RAMP_START * predicted_ratio(pad_across, offset) * MASS * G / (2 * MU)  # N
    pad = [0.01, pad_across, pad_along]
    return ecpsim.load_scene(str(SCENE), {
        "duration": 1.6,
        "solver.selection": "least_energy",
        "pairs.0.friction.mu": MU, "pairs.1.friction.mu": MU,
        "pairs.0.friction.e_r": E_R, "pairs.1.friction.e_r": E_R,
        "bodies.1.shape.box.size": pad, "bodies.2.shape.box.size": pad,
        "bodies.1.position": [-0.05, offset, 0.04], "bodies.2.position": [0.05, offset, 0.04],
        "grippers.0.force":
            f"t < 0.3 ? 0.2 : {force!r} * (t < {RAMP_FROM} ? 1 : 1 - {RAMP_RATE} * (t - {RAMP_FROM}))",
        "grippers.0.motion.waypoints": [{"t": 0.5, "position": [0, offset, 0.04]},
                                        {"t": 0.9, "position": [0, offset, 0.045]}],
    })


def turn_between(q0, q1):
    """rad: the angle of the rotation from quaternion q0 to q1 (w, x, y, z)."""
    return 2 * math.acos(min(1.0, abs(float(np.dot(q0, q1)))))


def slip_onset(pad_across, pad_along, offset):
    """One case: a dict of COLUMNS (held and slipped None if the box never slipped)."""
    scene = grasp_scene(pad_across, pad_along, offset)
    columns = ecpsim.run(scene)
    t = columns["t"]
    above = columns["box.pz"] - columns["left_jaw.pz"]
    q = np.stack([columns[f"box.q{c}"] for c in "wxyz"], axis=1)
    ratio = columns["hand.force"] * 2 * MU / (MASS * G)  # the step's force, at its start
    start = int(np.searchsorted(t, RAMP_FROM - 0.5 * scene.h))
    row = {"pad_across": pad_across, "pad_along": pad_along, "offset": offset,
           "centroid": centroid(pad_across, offset),
           "predicted": predicted_ratio(pad_across, offset),
           "held": None, "slipped": None, "turn": None}
    for i in range(start + 1, len(t)):
        turn = turn_between(q[start], q[i])
        if abs(above[i] - above[start]) > HELD or turn > HELD:
            row.update(held=float(ratio[i - 1]), slipped=float(ratio[i]), turn=turn)
            break
    return row


def write_table(rows, path):
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: ("" if row[k] is None else f"{row[k]:.6g}") for k in COLUMNS})
    return write_bytes_atomically(path, text.getvalue().encode())


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4.2))
    offsets = np.linspace(0, max(OFFSETS), 200)
    for (across, along), colour in zip(PADS, ["tab:blue", "tab:orange"]):
        label = f"{across * 100:g} × {along * 100:g} cm pads"
        axes.plot(offsets * 1e3, [predicted_ratio(across, d) for d in offsets], color=colour,
                  label=f"{label}: Coulomb, ellipsoid")
        mine = [r for r in rows if r["pad_across"] == across and r["held"] is not None]
        d = np.array([r["offset"] for r in mine]) * 1e3
        axes.plot(d, [r["held"] for r in mine], "^", color=colour, label=f"{label}: last held")
        axes.plot(d, [r["slipped"] for r in mine], "v", color=colour, mfc="none",
                  label=f"{label}: first slipped")
    axes.set_xlabel("grip offset from the CM d (mm)")
    axes.set_ylabel("2 μ F / m g")
    axes.set_title("Slip onset of a box held between two pads (least-energy selection)")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=7)
    figure.tight_layout()
    return save_figure_atomically(figure, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("-o", "--out", default="out/grasp_slip", help="output folder")
    parser.add_argument("--figure", help="also save the figure here (e.g. docs/figures/...)")
    args = parser.parse_args(argv)
    out = pathlib.Path(args.out)
    rows = [slip_onset(across, along, d) for across, along in PADS for d in OFFSETS]
    write_table(rows, out / "grasp_slip.csv")
    plot(rows, out / "grasp_slip_onset.png")
    if args.figure:
        plot(rows, pathlib.Path(args.figure))
    for r in rows:
        print(f"pads {r['pad_across'] * 100:g} cm, d = {r['offset'] * 1e3:4.1f} mm: predicted "
              f"{r['predicted']:.4f}, held at {r['held']}, slipped at {r['slipped']}")
    return 0 if all(r["held"] is not None for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
