"""examples/push_sweep.py: a small sweep on a LocalCluster of two processes equals the serial
run bit for bit, a fixed seed gives the same table, and its rows obey the push's physics:
a centred push turns nothing and reads μ m g on the finger's sensor."""

import math

import numpy as np
import pytest

import dask_cluster
import ecpsim
import push_sweep

G, MASS = 9.8, 1.0  # m/s², kg: push_sweep.yaml
# s: every finger (≥ 0.05 m/s from 1 cm behind) pushes for at least 0.3 s, a steady push
DURATION = 0.5
# relative to the weight: the finger's sticking friction made unique by the island's creep is
# −e² μ p_n v / ε (ε = 1e-5 V); the solver leaves v in error by its tolerance 1e-12 of V, and the
# box's vertical v, set by the ground's gap (held to 1e-12 of the box's length L), by
# 1e-12 L / h, so that friction is off by ≤ e² μ_pair p_n · 1e-7 (1 + L / (h V))
# (engine/README.md; tests/engine/body_contact_test.cpp). Here e = 1, μ_pair ≤ sqrt(0.5 × 0.7),
# p_n = μ m g h ≤ 0.7 m g h, L = sqrt(trace I / m) = 0.1225 m and V ≥ max(speed, g h)
BOX_LENGTH = math.sqrt((0.1**2 + 0.2**2 + 0.2**2) * 2 / 12)


def sticking_force_rel(speed):
    velocity = max(speed, G * 0.01)
    return 1e-7 * math.sqrt(0.5 * 0.7) * 0.7 * (1 + BOX_LENGTH / (0.01 * velocity))


# rad: a mirror-symmetric push turns the box only through the creep of its sticking contacts,
# ≤ 1e-5 V with V = g h + |v| ≤ 0.4 m/s, over a lever of the box's half-width 0.1 m, for 0.5 s
SYMMETRIC_TURN = 1e-5 * 0.4 / 0.1 * DURATION
# m: the box's back face rides on the finger to the solver's position error (1e-12 of the
# lengths) with margin, as tests/engine/manipulation_scenes_test.cpp's kPenetration
CONTACT_GAP = 1e-9
# m: a push this far off the CM line turns the box visibly (the smallest |push_y| in the cases
# below where the sign is asserted; a 1.2 mm offset already turns it 4°)
OFF_CENTRE = 0.005

SEED = 5
# pushes through the CM line, low enough (μ z ≤ 0.035 m < b/2) never to tip
CENTRED = [push_sweep.make_case(100 + i, mu, e_r, 0.0, 0.05, speed, DURATION)
           for i, (mu, e_r, speed) in enumerate([(0.2, 0.02, 0.1), (0.4, 0.05, 0.25),
                                                 (0.6, 0.09, 0.05), (0.7, 0.1, 0.3)])]


@pytest.fixture(scope="module")
def client():
    # the examples' own LocalCluster: two worker processes of one thread
    with dask_cluster.cluster_client(workers=2) as dask_client:
        yield dask_client


@pytest.fixture(scope="module")
def cases():
    return push_sweep.make_cases(36, SEED, DURATION) + CENTRED


@pytest.fixture(scope="module")
def serial_rows(cases):
    return push_sweep.run_sweep(cases)


def test_the_cluster_gives_the_serial_rows_bit_for_bit(client, cases, serial_rows):
    distributed = push_sweep.run_sweep(cases, client)
    assert len(distributed) == len(cases)
    # == on the dicts: every double identical, failures (if any) with the same message
    assert distributed == serial_rows
    assert [row["case"] for row in distributed] == [case["case"] for case in cases]


def test_a_fixed_seed_gives_the_same_table(client, serial_rows, tmp_path, capsys):
    assert push_sweep.make_cases(36, SEED, DURATION) == push_sweep.make_cases(36, SEED, DURATION)
    assert push_sweep.make_cases(8, SEED + 1, DURATION) != push_sweep.make_cases(8, SEED, DURATION)
    # the first k cases do not depend on the number of runs
    assert push_sweep.make_cases(8, SEED, DURATION) == push_sweep.make_cases(36, SEED, DURATION)[:8]
    # the command line on the running cluster (--scheduler), its table read back
    code = push_sweep.main(["--runs", "8", "--seed", str(SEED), "--duration", str(DURATION),
                            "--scheduler", client.scheduler.address, "-o", str(tmp_path)])
    assert code == 0
    assert "8 runs:" in capsys.readouterr().out
    assert push_sweep.read_table(tmp_path / "push_sweep.csv") == serial_rows[:8]
    assert (tmp_path / "push_sweep.csv").read_text() == push_sweep.table(serial_rows[:8])
    assert (tmp_path / "push_sweep.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["push_sweep.csv", "push_sweep.png"]


def test_a_centred_push_slides_the_box_straight_against_mu_m_g(serial_rows):
    rows = {row["case"]: row for row in serial_rows}
    weight = MASS * G
    for case in CENTRED:
        row = rows[case["case"]]
        assert row["failure"] == ""
        assert row["slid"] == 1 and row["tipped"] == 0
        assert abs(row["rotation"]) <= SYMMETRIC_TURN
        # the box rides on the finger: its CM 6 cm ahead of the finger's axis at the end
        finger_x = push_sweep.FINGER_START_X + case["speed"] * DURATION
        assert row["x"] == pytest.approx(finger_x + 0.01 + 0.05, abs=CONTACT_GAP)
        assert row["z"] == pytest.approx(0.1, abs=CONTACT_GAP)
        # the sensor reads the sliding friction against the push, and nothing else
        assert row["sensor_fx"] == pytest.approx(-case["mu"] * weight,
                                                 abs=sticking_force_rel(case["speed"]) * weight)
        assert abs(row["sensor_fy"]) <= sticking_force_rel(case["speed"]) * weight
        assert abs(row["sensor_fz"]) <= sticking_force_rel(case["speed"]) * weight


def test_a_row_is_what_run_writes_to_trajectory_csv(cases, serial_rows):
    # the final pose and the finger's sensor (`finger.fx fy fz`: WrenchOnOther, its one contact)
    # as ecpsim.run's columns: the same steps, the same doubles
    for case, row in ((cases[1], serial_rows[1]), (CENTRED[0], serial_rows[-len(CENTRED)])):
        columns = ecpsim.run(push_sweep.push_scene(case))
        for name, column in (("x", "box.px"), ("y", "box.py"), ("z", "box.pz"), ("qw", "box.qw"),
                             ("qz", "box.qz"), ("sensor_fx", "finger.fx"),
                             ("sensor_fy", "finger.fy"), ("sensor_fz", "finger.fz")):
            assert row[name] == columns[column][-1], (case["case"], name)


def test_an_off_centre_push_turns_the_box_away_from_the_push_point(serial_rows):
    # a push along +x at +y exerts a moment −y F about z: the box turns clockwise, and mirrored
    turned = [r for r in serial_rows
              if not r["failure"] and not r["tipped"] and abs(r["push_y"]) >= OFF_CENTRE]
    assert len(turned) >= 20
    for row in turned:
        assert np.sign(row["rotation"]) == -np.sign(row["push_y"]), row


def test_bad_input_is_named(capsys, tmp_path):
    assert push_sweep.main(["--runs", "0", "-o", str(tmp_path)]) == 1
    assert "--runs = 0" in capsys.readouterr().err
    assert push_sweep.main(["--runs", "2", "--duration", "-1", "--serial",
                            "-o", str(tmp_path)]) == 1
    assert "duration = -1" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
