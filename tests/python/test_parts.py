"""Bodies made of convex parts from Python: a contact per pair of parts in contacts(), and the
pair's combined columns in run()'s trajectory (docs/scene_format.md, "Decomposition")."""

import numpy as np

import ecpsim


def test_a_cube_in_a_cup_rests_on_the_floor_part(scenes):
    scene = ecpsim.load_scene(str(scenes / "cube_in_cup.yaml"))
    sim = ecpsim.Simulation(scene)
    sim.step(round(1.0 / scene.h))
    cube = sim.body_names.index("cube")
    assert abs(sim.positions[cube, 2] - 0.03) < 1e-9
    # the cup touches the cube through each of its five parts: "cup[i].cube"
    between = [c for c in sim.contacts() if c["other"] == "cube"]
    assert [c["name"] for c in between] == [f"cup[{i}].cube" for i in range(5)]
    assert [c["part"] for c in between] == list(range(5))
    assert all(c["other_part"] is None for c in between)
    weight = 0.05 * 9.8
    np.testing.assert_allclose([c["f_n"] for c in between], [weight, 0, 0, 0, 0], atol=1e-9)
    # trajectory.csv's one set of columns for the pair holds their combination
    columns = ecpsim.run(scene, duration=1.0, every=100)
    assert "cup.cube.fn" in columns and "cup[0].cube.fn" not in columns
    assert abs(columns["cup.cube.fn"][-1] - weight) < 1e-9


def test_under_auto_a_pair_lists_the_hulls_contact_then_the_parts(scenes):
    # the cube in the cup: the hulls' contact is left out, the parts' carry the weight
    scene = ecpsim.load_scene(str(scenes / "cube_in_cup.yaml"),
                              {"bodies.0.decomposition": "auto"})
    sim = ecpsim.Simulation(scene)
    sim.step(round(1.0 / scene.h))
    between = [c for c in sim.contacts() if c["other"] == "cube"]
    assert [c["sides"] for c in between] == ["hulls"] + ["parts"] * 5
    assert [c["name"] for c in between] == ["cup.cube"] + [f"cup[{i}].cube" for i in range(5)]
    assert between[0]["p_n"] == 0
    np.testing.assert_allclose(sum(c["f_n"] for c in between[1:]), 0.05 * 9.8, atol=1e-9)
