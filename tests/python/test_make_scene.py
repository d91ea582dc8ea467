"""make_scene: scenes built in Python, validated like files, stepping like their YAML twins."""

import numpy as np
import pytest

import ecpsim

# m: a kinematic body's position, start + v t, to a few ulps of its 1 m coordinate
KINEMATIC_ROUNDOFF_TOL = 1e-15

SLIDE = dict(
    bodies=[{"name": "box", "box": [0.5, 0.5, 0.1], "mass": 15, "position": [0, 0, 0.05],
             "velocity": [0.5, 0, 0]}],
    h=0.01, duration=0.5, gravity=[0, 0, -9.8],
    friction={"mu": 0.22, "e_t": 1, "e_o": 1, "e_r": 0.1})


def test_built_slide_steps_as_the_file(scenes):
    built = ecpsim.make_scene(**SLIDE)
    assert built.body_names == ["box"] and built.contact_names == ["box.ground"]
    from_file = ecpsim.load_scene(str(scenes / "slide.yaml"))
    a, b = ecpsim.Simulation(built), ecpsim.Simulation(from_file)
    a.step(30)
    b.step(30)
    # the same body, obstacle, friction and settings: the same doubles
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.velocities, b.velocities)


def test_mesh_body_kinematic_body_and_loads(scenes):
    scene = ecpsim.make_scene(
        bodies=[{"name": "tbar", "mesh": str(scenes / "meshes" / "tbar.obj"), "mass": 1,
                 "position": [0, 0, 0.5]},
                {"name": "finger", "box": [0.02, 0.02, 0.05], "mass": 1,
                 "position": [-1, 0, 0.05], "kinematic": {"velocity": [0.1, 0, 0]}}],
        loads=[{"body": "tbar", "torque": [0, 0, "0.1*sin(t)"], "end": 0.5}],
        duration=0.2)
    assert scene.bodies[1]["kinematic"]
    assert "tbar.finger" in scene.contact_names
    sim = ecpsim.Simulation(scene)
    sim.step(5)
    np.testing.assert_allclose(sim.positions[1], [-1 + 0.1 * 0.05, 0, 0.05], rtol=0,
                               atol=KINEMATIC_ROUNDOFF_TOL)


def test_validation_messages():
    bad = dict(SLIDE, bodies=[dict(SLIDE["bodies"][0], mass=-15)])
    with pytest.raises(ecpsim.InputError, match=r"bodies\[0\].mass = -15: expected a mass"):
        ecpsim.make_scene(**bad)
    inside = dict(SLIDE, bodies=[dict(SLIDE["bodies"][0], position=[0, 0, -0.35])])
    with pytest.raises(ecpsim.InputError, match=r"bodies\[0\].position.*inside"):
        ecpsim.make_scene(**inside)
    with pytest.raises(ecpsim.InputError, match=r"bodies\[0\].colour: unknown key"):
        ecpsim.make_scene(**dict(SLIDE, bodies=[dict(SLIDE["bodies"][0], colour="red")]))
    with pytest.raises(ecpsim.InputError, match=r"h = .*expected"):
        ecpsim.make_scene(**dict(SLIDE, h=-1))
    with pytest.raises(ecpsim.InputError, match=r"loads\[0\].force\[0\] = \"t\*\*\*\""):
        ecpsim.make_scene(**SLIDE, loads=[{"body": "box", "force": ["t***", 0, 0]}])
