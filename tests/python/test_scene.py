"""load_scene: the scene views, --set overrides and the loader's file:line messages."""

import numpy as np
import pytest

import ecpsim

# relative: the loader's box inertia, a few flops from the typed mass and size
INERTIA_REL_TOL = 1e-14


def test_slide_scene_views(scenes):
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"))
    assert scene.h == 0.01
    assert scene.duration == 0.5
    np.testing.assert_array_equal(scene.gravity, [0, 0, -9.8])
    assert scene.body_names == ["box"]
    assert scene.model == "auto"
    box = scene.bodies[0]
    assert box["mass"] == 15
    assert not box["kinematic"]
    # a 15 kg box 0.5 × 0.5 × 0.1 m: I_zz = m (a² + b²) / 12
    assert box["inertia"][2, 2] == pytest.approx(15 / 12 * (0.5**2 + 0.5**2), rel=INERTIA_REL_TOL)
    np.testing.assert_array_equal(box["quaternion"], [1, 0, 0, 0])
    np.testing.assert_array_equal(box["velocity"], [0.5, 0, 0])
    assert [o["name"] for o in scene.obstacles] == ["ground"]
    assert scene.obstacles[0]["friction"]["mu"] == 0.22
    assert scene.contact_names == ["box.ground"]


def test_overrides_as_dict_and_as_set_strings(scenes):
    path = str(scenes / "slide.yaml")
    from_dict = ecpsim.load_scene(path, {"bodies.0.mass": 3, "h": 0.005,
                                         "bodies.0.velocity": [0.25, 0, 0],
                                         "model": "planar"})
    from_strings = ecpsim.load_scene(path, ["bodies.0.mass=3", "h=0.005",
                                            "bodies.0.velocity=[0.25, 0, 0]", "model=planar"])
    for scene in (from_dict, from_strings):
        assert scene.bodies[0]["mass"] == 3
        assert scene.h == 0.005
        np.testing.assert_array_equal(scene.bodies[0]["velocity"], [0.25, 0, 0])
        assert scene.model == "planar"
    # a numpy value reads as its number
    assert ecpsim.load_scene(path, {"h": np.float64(0.002)}).h == 0.002


def test_paths_may_be_pathlib_paths(scenes):
    # a pathlib.Path wherever a path is taken, as str
    assert ecpsim.load_scene(scenes / "slide.yaml").source == str(scenes / "slide.yaml")
    tbar = {"duration": 1, "bodies": [{"name": "t", "mesh": "meshes/tbar.obj", "mass": 2,
                                       "position": [0, 0, 1]}]}
    assert ecpsim.make_scene(tbar, base_dir=scenes).body_names == ["t"]
    assert ecpsim.hull(scenes / "meshes" / "tbar.obj")["volume"] > 0


def test_a_string_override_stays_a_string(scenes):
    # "t < 0.3 ? 0.2 : 3" parsed as YAML is a mapping {t < 0.3 ? 0.2: 3}; from a dict it is the
    # gripper's force expression, 3 N after 0.3 s, as the same --set quoted on the command line
    path = str(scenes / "gripper.yaml")
    force = "t < 0.3 ? 0.2 : 3"
    from_dict = ecpsim.load_scene(path, {"grippers.0.force": force})
    quoted = ecpsim.load_scene(path, [f'grippers.0.force="{force}"'])
    a, b = ecpsim.Simulation(from_dict), ecpsim.Simulation(quoted)
    a.step(70)
    b.step(70)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert a.positions.tolist() != ecpsim.Simulation(ecpsim.load_scene(path)).positions.tolist()
    # quotes and backslashes inside survive too: the loader sees the string, and names it
    with pytest.raises(ecpsim.InputError, match=r'grippers\.0\.force=.*a \\"b'):
        ecpsim.load_scene(path, {"grippers.0.force": 'a \\"b'})


def test_override_errors_carry_the_set_message(scenes):
    path = str(scenes / "slide.yaml")
    with pytest.raises(ecpsim.InputError) as error:
        ecpsim.load_scene(path, {"bodies.0.mass": -2})
    assert "--set bodies.0.mass=-2" in str(error.value)
    assert "expected a finite mass" in str(error.value)
    with pytest.raises(ecpsim.InputError, match=r"--set durration=1"):
        ecpsim.load_scene(path, {"durration": 1})
    # a NaN is named as YAML's .nan, refused as non-finite
    with pytest.raises(ecpsim.InputError, match=r"\.nan"):
        ecpsim.load_scene(path, {"h": float("nan")})


def test_file_errors_name_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("h: 0.01\nduration: 1\nbodies:\n  - mass: -2\n"
                   "    shape: {box: {size: [1, 1, 1]}}\n")
    with pytest.raises(ecpsim.InputError) as error:
        ecpsim.load_scene(str(bad))
    # the CLI's message (tests/app/run_command_test.cpp)
    assert f"{bad}:4:11: bodies[0].mass = -2: expected a finite mass > 0 kg" in str(error.value)
    # InputError is a ValueError, so generic handlers catch it
    assert isinstance(error.value, ValueError)


def test_missing_file(tmp_path):
    with pytest.raises(ecpsim.InputError, match="nothing.yaml"):
        ecpsim.load_scene(str(tmp_path / "nothing.yaml"))
