"""run(): the trajectory as numpy columns, the same columns and numbers as `ecpsim run`'s CSV."""

import csv
import os
import pathlib
import subprocess

import numpy as np
import pytest

import ecpsim

BINARY_DIR = pathlib.Path(os.environ.get("ECPSIM_BINARY_DIR", "build"))
# s: a row's t, k steps of h, to a few ulps of 0.1 s
TIME_ROUNDOFF_TOL = 1e-15


def read_csv(path):
    """The header, the numeric columns as an array, and the model columns (text) by name."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    numeric = [i for i, name in enumerate(rows[0]) if not name.endswith("model")]
    text = {rows[0][i]: [row[i] for row in rows[1:]]
            for i in range(len(rows[0])) if i not in numeric}
    return (rows[0], [rows[0][i] for i in numeric],
            np.array([[float(row[i]) for i in numeric] for row in rows[1:]]), text)


@pytest.mark.parametrize("name", ["slide.yaml", "push_box.yaml"])
def test_run_equals_the_cli_csv(scenes, tmp_path, name):
    cli = BINARY_DIR / "app" / "ecpsim"
    if not cli.exists():
        pytest.fail(f"{cli}: the CLI is needed to compare with (build it first)")
    out = tmp_path / "out"
    overrides = {"duration": 0.3, "output.every": 7}
    subprocess.run([str(cli), "run", str(scenes / name), "-o", str(out)]
                   + ["--set", "duration=0.3", "--set", "output.every=7"],
                   check=True, capture_output=True)
    header, numeric, values, text = read_csv(out / "trajectory.csv")
    trajectory = ecpsim.run(ecpsim.load_scene(str(scenes / name), overrides))
    assert list(trajectory) == header
    for i, column in enumerate(numeric):
        # the CSV holds shortest round-trip decimals: the same doubles
        np.testing.assert_array_equal(trajectory[column], values[:, i], err_msg=column)
    assert text, "a model column per body"
    for column, models in text.items():
        assert list(trajectory[column]) == models, column
        assert models[0] == "initial"


def test_run_rows_follow_every_and_duration(scenes):
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"))
    trajectory = ecpsim.run(scene, duration=0.1, every=3)
    # t = 0, steps 3, 6, 9 and the last, 10
    np.testing.assert_allclose(trajectory["t"], [0, 0.03, 0.06, 0.09, 0.1], rtol=0,
                               atol=TIME_ROUNDOFF_TOL)
    # the same states a Simulation reaches
    sim = ecpsim.Simulation(scene)
    sim.step(10)
    assert trajectory["vx"][-1] == sim.velocities[0, 0]
    assert trajectory["qw"][0] == 1
    with pytest.raises(ecpsim.InputError, match="every = 0"):
        ecpsim.run(scene, every=0)
    with pytest.raises(ecpsim.InputError, match="duration = -1"):
        ecpsim.run(scene, duration=-1)


def test_run_raises_the_solver_failure(scenes):
    scene = ecpsim.load_scene(str(scenes / "tilted_box.yaml"), {"solver.max_iterations": 1})
    with pytest.raises(ecpsim.SolverFailure, match="residual"):
        ecpsim.run(scene)
