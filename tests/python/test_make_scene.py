"""make_scene: the YAML format's tree as a Python dict, read by the file's loader and checks."""

import copy
import warnings

import numpy as np
import pytest

import ecpsim

# m: a kinematic body's position, start + v t, to a few ulps of its 1 m coordinate
KINEMATIC_ROUNDOFF_TOL = 1e-15

# scenes/slide.yaml as a dict
SLIDE = {
    "gravity": [0, 0, -9.8], "h": 0.01, "duration": 0.5,
    "ground": {"friction": {"mu": 0.22, "e_t": 1, "e_o": 1, "e_r": 0.1}},
    "bodies": [{"name": "box", "shape": {"box": {"size": [0.5, 0.5, 0.1]}}, "mass": 15,
                "position": [0, 0, 0.05], "velocity": [0.5, 0, 0]}],
}


def slide(**changes):
    """SLIDE with its body's keys changed (None removes one)."""
    tree = copy.deepcopy(SLIDE)
    for key, value in changes.items():
        if value is None:
            del tree["bodies"][0][key]
        else:
            tree["bodies"][0][key] = value
    return tree


def test_the_slide_as_a_dict_steps_as_the_file(scenes):
    built = ecpsim.make_scene(SLIDE)
    assert built.body_names == ["box"] and built.contact_names == ["box.ground"]
    from_file = ecpsim.load_scene(str(scenes / "slide.yaml"))
    a, b = ecpsim.Simulation(built), ecpsim.Simulation(from_file)
    a.step(30)
    b.step(30)
    # the same body, obstacle, friction and settings: the same doubles
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.velocities, b.velocities)


def test_numpy_values_and_every_file_route_feature(scenes):
    # a mesh (relative to base_dir), on_ground, rpy, a kinematic finger with waypoints, a
    # sphere, a pair's friction and a load given as expressions
    tree = {
        "duration": 0.2,
        "ground": {"friction": {"mu": np.float64(0.3)}},
        "bodies": [
            {"name": "tbar", "mesh": "meshes/tbar.obj", "mass": 2, "on_ground": True,
             "position": np.array([0.0, 0.0]), "rpy": [0, 0, 90]},
            {"name": "ball", "shape": {"sphere": {"radius": 0.02}}, "mass": 0.1,
             "position": [0.5, 0.5, 0.02]},
            {"name": "finger", "kinematic": True, "shape": {"box": {"size": [0.02, 0.02, 0.05]}},
             "motion": {"waypoints": [{"t": 0, "position": [-1, 0, 0.05]},
                                      {"t": 1, "position": [-0.9, 0, 0.05]}]}},
        ],
        "pairs": [{"bodies": ["tbar", "finger"], "friction": {"mu": 0.5}}],
        "loads": [{"body": "tbar", "torque": [0, 0, "0.1*sin(t)"], "end": 0.1}],
    }
    scene = ecpsim.make_scene(tree, base_dir=str(scenes))
    assert scene.bodies[2]["kinematic"]
    assert "tbar.finger" in scene.contact_names
    assert scene.obstacles[0]["friction"]["mu"] == 0.3
    sim = ecpsim.Simulation(scene)
    sim.step(5)
    np.testing.assert_allclose(sim.positions[2], [-1 + 0.1 * 0.05, 0, 0.05], rtol=0,
                               atol=KINEMATIC_ROUNDOFF_TOL)


def test_errors_name_the_key_path_as_the_file_loader_does():
    cases = [
        (slide(mass=-15), r"make_scene: bodies\[0\]\.mass = -15: expected a finite mass > 0 kg"),
        (slide(mass=None), r"make_scene: bodies\[0\]\.mass = \(missing\)"),
        (slide(colour="red"), r"make_scene: bodies\[0\]\.colour: unknown key"),
        (slide(positon=[0, 0, 0.05]),
         r"make_scene: bodies\[0\]\.positon: unknown key \(did you mean \"position\"\?\)"),
        (slide(position=[0, 0, -0.35]), r"make_scene: bodies\[0\]\.position = .*inside"),
        (dict(SLIDE, h=-1), r"make_scene: h = -1: expected"),
        (dict(SLIDE, loads=[{"body": "box", "force": ["t***", 0, 0]}]),
         r"make_scene: loads\[0\]\.force\[0\] = \"t\*\*\*\": Unexpected operator"),
    ]
    for tree, message in cases:
        with pytest.raises(ecpsim.InputError, match="^" + message):
            ecpsim.make_scene(tree)


def test_a_string_stays_a_string():
    # "t < 0.3 ? 0.2 : 3" read as YAML would be a mapping; from Python it is the expression
    tree = dict(SLIDE, loads=[{"body": "box", "force": ["t < 0.3 ? 0.2 : 3", 0, 0]}])
    ecpsim.make_scene(tree)
    for given in ({"loads": [{"body": "box", "force": [0, 0, 0]}]},):
        scene = ecpsim.make_scene(dict(SLIDE, **given),
                                  {"loads.0.force.0": "t < 0.3 ? 0.2 : 3"})
        assert scene.body_names == ["box"]


def test_units_and_mesh_warnings_reach_python(scenes, tmp_path):
    # a mesh written in millimetres read as metres is 568 m across: a SceneWarning, and with
    # `units: mm` none
    mesh = (scenes / "meshes" / "tbar.obj").read_text()
    big = tmp_path / "big.obj"
    big.write_text("\n".join(
        " ".join(["v"] + [str(1000 * float(x)) for x in line.split()[1:]])
        if line.startswith("v ") else line for line in mesh.splitlines()))
    tree = dict(SLIDE, bodies=[{"name": "tbar", "mesh": str(big), "mass": 2, "on_ground": True,
                                "position": [0, 0]}])
    with pytest.warns(ecpsim.SceneWarning,
                      match=r"bodies\[0\]\.mesh: .*big\.obj is 568 m across.*units: mm"):
        scene = ecpsim.make_scene(tree)
    assert scene.warnings and issubclass(ecpsim.SceneWarning, UserWarning)
    tree["bodies"][0]["units"] = "mm"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ecpsim.make_scene(tree)


def test_the_default_ground_and_gravity_are_the_files():
    # no `ground` key: no obstacle, as in a file; the body falls freely
    tree = {"duration": 0.1, "bodies": [{"name": "b", "shape": {"box": {"size": [1, 1, 1]}},
                                         "mass": 1, "position": [0, 0, 5]}]}
    sim = ecpsim.Simulation(ecpsim.make_scene(tree))
    sim.step(10)
    assert sim.velocities[0, 2] < 0 and sim.scene.contact_names == []
