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


def test_validation_names_the_argument_key_value_and_expectation():
    # the scene passes ValidateScene, each problem named by make_scene's own keys
    cases = [
        (dict(SLIDE, h=0), r"h = 0: expected a finite time step > 0 s: a time in \[1e-150"),
        (dict(SLIDE, gravity=[0, 0, 1e200]),
         r"gravity = \[0, 0, 1e\+200\]: expected a gravity \[x, y, z\] in m/s², each a finite"),
        # the default ground's friction is the `friction` argument
        (dict(SLIDE, friction={"mu": -0.5}),
         r"friction\.mu = -0\.5: expected a friction coefficient >= 0 .* for obstacle \"ground\""),
        (dict(SLIDE, bodies=[dict(SLIDE["bodies"][0], friction={"mu": -1})]),
         r"bodies\[0\]\.friction\.mu = -1: expected a friction coefficient >= 0 .* the contact "
         r"of body \"box\" with obstacle \"ground\""),
        (dict(SLIDE, obstacles=[{"name": "floor", "friction": {"e_r": 0}}]),
         r"obstacles\[0\]\.friction\.e_r = 0: expected a torsional ellipsoid semi-axis > 0 m, "
         r"or `patch`, for obstacle \"floor\""),
        (dict(SLIDE, friction={"e_r": "pach"}),
         r"friction\.e_r = 'pach': expected a torsional ellipsoid semi-axis > 0 m, or \"patch\""),
        (dict(SLIDE, bodies=[dict(SLIDE["bodies"][0], box=[1e20, 1e20, 1e20])]),
         r"bodies\[0\]\.box = 1\.73\d*e\+20 m across: expected a mesh of body \"box\""),
        (dict(SLIDE, loads=[{"body": "box", "force": [1, 0, 0], "start": 0.5, "end": 0.2}]),
         r"loads\[0\]\.end = 0\.2: expected an end time \(s\) > start = 0\.5"),
    ]
    for arguments, message in cases:
        with pytest.raises(ecpsim.InputError, match="^" + message):
            ecpsim.make_scene(**arguments)


def test_e_r_patch_is_read_as_in_a_scene_file_and_reported_back():
    # `e_r: patch` (docs/scene_format.md): the ground's, and a body's number over it
    scene = ecpsim.make_scene(**dict(SLIDE, friction={"mu": 0.3, "e_r": "patch"}))
    assert scene.obstacles[0]["friction"]["e_r"] == "patch"
    body = dict(SLIDE["bodies"][0], friction={"e_r": 0.05})
    scene = ecpsim.make_scene(**dict(SLIDE, friction={"e_r": "patch"}, bodies=[body]))
    assert scene.bodies[0]["friction"]["e_r"] == 0.05
    sim = ecpsim.Simulation(scene)
    sim.step()
    assert sim.time > 0
