"""examples/grasp_slip.py: a centred grip slips where 2 μ F = m g, within one step of its force
ramp, and the table and figure are written."""

import csv

import grasp_slip

# the ramp's change of 2 μ F / m g in one 10 ms step: half the starting 1.15 per second
RAMP_STEP = grasp_slip.RAMP_START * grasp_slip.RAMP_RATE * 0.01


def test_a_centred_grip_slips_where_its_friction_equals_the_weight():
    row = grasp_slip.slip_onset(0.04, 0.03, 0.0)
    assert row["predicted"] == 1.0
    assert row["slipped"] < 1.0 <= row["held"]
    assert row["held"] - row["slipped"] <= RAMP_STEP * (1 + 1e-9)
    assert row["turn"] < grasp_slip.HELD  # centred: it slides, it does not turn


def test_the_table_and_figure_are_written(tmp_path):
    rows = [grasp_slip.slip_onset(0.02, 0.015, 0.0)]
    grasp_slip.write_table(rows, tmp_path / "grasp_slip.csv")
    grasp_slip.plot(rows, tmp_path / "grasp_slip_onset.png")
    with open(tmp_path / "grasp_slip.csv") as file:
        table = list(csv.DictReader(file))
    assert [r["offset"] for r in table] == ["0"]
    assert float(table[0]["slipped"]) < 1.0 <= float(table[0]["held"])
    assert (tmp_path / "grasp_slip_onset.png").stat().st_size > 0
