"""examples/tbar_closed_loop.py: the PD controller brings the T-bar to its goal and stops where
Coulomb friction's dead zone says, flat on the table all along; its plot is written."""

import math

import numpy as np
import pytest

import ecpsim
import tbar_closed_loop

# relative: at rest the controller's wrench lies in the friction ellipsoid (dead_zone_ratio ≤ 1)
# up to what the solver leaves of the friction rows, its tolerance 1e-12 of each row's scale,
# with a margin for the ellipsoid's square root and the wrench's components summed
DEAD_ZONE_REL = 1e-9
# m/s: at rest a sticking contact creeps at most 1e-9 of the velocity scale |g| h (docs/python.md,
# contact modes), here 1e-9 × 9.8 m/s² × 0.01 s
REST_SPEED = 1e-9 * 9.8 * 0.01
# s: long enough for the loop (ω = 60 rad/s, saturated at 10 N) to settle from the default goal
# 0.29 m and 60° away and for the contact's slip to decay to the creep; 200 steps
SETTLE_TIME = 2.0
# relative: the example's dead zones and their closed forms here are the same two flops
CLOSED_FORM_REL_TOL = 1e-15

GOAL = (0.25, 0.15, math.radians(150))  # m, m, rad: from (0, 0, 90°)


def test_the_t_stops_at_the_goal_within_the_friction_dead_zone():
    result = tbar_closed_loop.run_closed_loop(GOAL, SETTLE_TIME)
    # it started far outside the dead zone ...
    assert np.linalg.norm(result.error[0, :2]) > 100 * result.position_dead_zone
    # ... and came to rest inside it: no closer is possible for a PD against static friction
    assert result.final_speed + result.final_spin * 0.1 <= REST_SPEED  # e_r = 0.1 m
    assert result.dead_zone_ratio <= 1 + DEAD_ZONE_REL
    assert np.linalg.norm(result.final_error[:2]) <= result.position_dead_zone * (1 + DEAD_ZONE_REL)
    assert abs(result.final_error[2]) <= result.yaw_dead_zone * (1 + DEAD_ZONE_REL)
    # the contact with the table held: it slid, then stuck, never separated, every step solved
    assert set(result.modes) == {"sliding", "sticking"}
    assert result.modes[-1] == "sticking"
    assert result.converged.all()
    assert len(result.time) == round(SETTLE_TIME / 0.01)


def test_the_dead_zone_is_the_closed_form_of_the_gains():
    result = tbar_closed_loop.run_closed_loop(GOAL, 0.01)
    # μ m g / kp and μ m g e_r / kp_yaw with tbar.yaml's μ = 0.22, e_r = 0.1 m, m = 2 kg
    holding = 0.22 * 2 * 9.8
    assert result.gains["kp"] == 2 * 60.0 ** 2
    assert math.isclose(result.position_dead_zone, holding / result.gains["kp"],
                        rel_tol=CLOSED_FORM_REL_TOL)
    assert math.isclose(result.yaw_dead_zone, holding * 0.1 / result.gains["kp_yaw"],
                        rel_tol=CLOSED_FORM_REL_TOL)


def test_main_writes_the_plot_and_maps_errors_to_the_cli_exit_codes(tmp_path, capsys):
    assert tbar_closed_loop.main(["-o", str(tmp_path), "--duration", "0.5"]) == 0
    plot = tmp_path / "tbar_closed_loop.png"
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == [plot.name]  # no temporary left behind
    assert "final error after 0.50 s" in capsys.readouterr().out
    assert tbar_closed_loop.main(["-o", str(tmp_path), "--duration", "-1"]) == 1
    assert "make_scene: duration = -1.0: expected a finite duration > 0 s" in capsys.readouterr().err
    assert tbar_closed_loop.main(["-o", str(tmp_path), "--omega", "0"]) == 1
    assert "controller omega = 0.0: expected a finite value > 0" in capsys.readouterr().err


def test_bad_controller_is_an_input_error():
    with pytest.raises(ecpsim.InputError, match=r"controller force_max = nan: expected"):
        tbar_closed_loop.Controller(force_max=math.nan)
