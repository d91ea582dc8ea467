"""A kinematic body's force/torque sensor and the contacts as arrays: the numbers of
trajectory.csv and of contacts()' dicts, without the dicts."""

import numpy as np
import pytest

import ecpsim

WRENCH = ["fx", "fy", "fz", "mx", "my", "mz"]
STEPS = 120  # 1.2 s of push_box: the pusher touches the box at about 0.4 s and pushes it on


def test_the_sensor_reads_the_trajectory_columns(scenes):
    scene = ecpsim.load_scene(str(scenes / "push_box.yaml"))
    columns = ecpsim.run(scene, duration=STEPS * scene.h, every=1)
    sim = ecpsim.Simulation(scene)
    np.testing.assert_array_equal(sim.sensor("pusher"), np.zeros(6))
    pushed = 0
    for row in range(1, STEPS + 1):
        sim.step()
        reading = sim.sensor("pusher")
        assert reading.shape == (6,)
        # the same doubles as trajectory.csv's pusher.fx … pusher.mz
        np.testing.assert_array_equal(reading, [columns[f"pusher.{c}"][row] for c in WRENCH])
        pushed += reading[0] < 0  # the box pushes back along −x
    assert pushed > STEPS / 2
    # by index too; a dynamic body has no sensor
    np.testing.assert_array_equal(sim.sensor(1), sim.sensor("pusher"))
    with pytest.raises(ecpsim.InputError, match=r"^sensor: body 'box' is dynamic"):
        sim.sensor("box")
    with pytest.raises(ecpsim.InputError, match=r"sensor: body = 'hand'"):
        sim.sensor("hand")


def test_contacts_as_arrays_hold_the_dicts_numbers(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    sim.step(60)
    listed = sim.contacts()
    arrays = sim.contacts(as_arrays=True)
    assert arrays["name"] == [c["name"] for c in listed] == sim.scene.contact_names
    for key in ["body", "other", "mode", "model"]:
        assert arrays[key] == [c[key] for c in listed]
    for key in ["other_is_body", "p_n", "p_t", "p_o", "p_r", "sigma", "f_n", "f_t", "f_o", "f_r"]:
        assert arrays[key].shape == (len(listed),)
        np.testing.assert_array_equal(arrays[key], [c[key] for c in listed])
    for key in ["a1", "a2", "normal", "tangent", "tangent2", "force"]:
        assert arrays[key].shape == (len(listed), 3)
        np.testing.assert_array_equal(arrays[key], [c[key] for c in listed])
    assert "sliding" in arrays["mode"] or "sticking" in arrays["mode"]
