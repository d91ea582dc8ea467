"""Batched rollouts (ecpsim.rollout) against stepping each Simulation alone, and domain
randomization on a live Simulation (set_mass, set_inertia, set_friction) against loading the scene
with the same values as overrides (issue 32, item 4)."""

import numpy as np
import pytest

import ecpsim

FIELDS = ("positions", "quaternions", "velocities", "angular_velocities")


def alone(sim, steps, controls=None):
    """The rollout's arrays of one simulation, stepped from Python: (steps, n, ...) per field."""
    rows = {key: [] for key in FIELDS + ("time", "converged")}
    for k in range(steps):
        if controls is not None:
            for b, wrench in enumerate(controls[k]):
                if wrench.any():
                    sim.apply_wrench(b, force=wrench[:3], torque=wrench[3:])
        sim.step()
        for key in FIELDS:
            rows[key].append(getattr(sim, key))
        rows["time"].append(sim.time)
        rows["converged"].append(sim.last_report["converged"])
    return {key: np.array(value) for key, value in rows.items()}


def assert_rows_equal(result, i, expected, what=""):
    """Simulation i's rows of a rollout equal `expected` to the bit."""
    for key, value in expected.items():
        np.testing.assert_array_equal(result[key][i], value, err_msg=f"{what} {key}")


# ---- rollout ----------------------------------------------------------------------------------


def test_rollout_equals_each_simulation_stepped_alone_on_any_thread_count(scenes):
    # different scenes of one body each (the desk's loads are expressions of t), started from
    # different states: one simulation stepped 5 steps before the rollout
    loaded = [ecpsim.load_scene(str(scenes / name)) for name in ("desk.yaml", "tbar.yaml")]
    loaded.append(ecpsim.load_scene(str(scenes / "slide.yaml")))
    loaded.append(ecpsim.load_scene(str(scenes / "desk.yaml"), {"bodies.0.velocity": [0, 0.4, 0]}))
    steps = 25

    def fresh():
        sims = [ecpsim.Simulation(scene) for scene in loaded]
        sims[1].step(5)
        return sims

    expected = [alone(sim, steps) for sim in fresh()]
    for threads in (1, 2, 3, None):
        sims = fresh()
        result = ecpsim.rollout(sims, steps, threads=threads)
        assert result["positions"].shape == (4, steps, 1, 3)
        assert result["quaternions"].shape == (4, steps, 1, 4)
        assert result["time"].shape == result["converged"].shape == (4, steps)
        assert result["converged"].dtype == bool and result["converged"].all()
        for i, sim in enumerate(sims):
            assert_rows_equal(result, i, expected[i], f"threads={threads} simulation {i}")
            # each simulation is left where its last row is
            assert sim.steps == steps + (5 if i == 1 else 0)
            np.testing.assert_array_equal(sim.positions, result["positions"][i, -1])


def test_controls_act_as_apply_wrench(scenes):
    # a push and a twist per step on the slide's box, and a kinematic finger (zero rows) beside
    # a pushed box of the same body count
    rng = np.random.default_rng(32)
    steps = 20
    slide = ecpsim.load_scene(str(scenes / "slide.yaml"))
    push = ecpsim.load_scene(str(scenes / "push_box.yaml"))
    # pushes below the weights (the slide's box 147 N, the pushed box's 9.8 N)
    controls = np.zeros((3, steps, 2, 6))
    for i in range(3):
        controls[i, :, 0, :3] = rng.uniform(-2, 2, (steps, 3))
        controls[i, :, 0, 5] = rng.uniform(-0.1, 0.1, steps)
    # the slide has one body: two slides and a push box make three simulations of 1 and 2
    # bodies, which cannot stack; roll the slides and the push box apart
    slides = [ecpsim.Simulation(slide) for _ in range(2)]
    result = ecpsim.rollout(slides, steps, threads=2, controls=controls[:2, :, :1])
    for i in range(2):
        expected = alone(ecpsim.Simulation(slide), steps, controls[i, :, :1])
        assert_rows_equal(result, i, expected, f"slide {i}")
    assert not np.array_equal(result["positions"][0], result["positions"][1])
    pushes = [ecpsim.Simulation(push) for _ in range(2)]
    result = ecpsim.rollout(pushes, steps, threads=2, controls=controls[1:])
    for i in range(2):
        expected = alone(ecpsim.Simulation(push), steps, controls[1 + i])
        assert_rows_equal(result, i, expected, f"push_box {i}")


def test_bad_arguments_raise_input_error_before_any_step(scenes):
    slide = ecpsim.load_scene(str(scenes / "slide.yaml"))
    push = ecpsim.load_scene(str(scenes / "push_box.yaml"))
    sims = [ecpsim.Simulation(slide) for _ in range(2)]
    pushes = [ecpsim.Simulation(push) for _ in range(2)]
    kinematic = np.zeros((2, 3, 2, 6))
    kinematic[1, 2, 1, 0] = 1.0  # the pusher
    cases = [
        (lambda: ecpsim.rollout([], 3), r"^rollout: simulations = \[\]"),
        (lambda: ecpsim.rollout(sims, 0), r"^rollout: steps = 0: expected steps ≥ 1"),
        (lambda: ecpsim.rollout(sims, 3, threads=0), r"^rollout: threads = 0"),
        (lambda: ecpsim.rollout([sims[0], 3], 3), r"^rollout: simulations\[1\] = 3"),
        (lambda: ecpsim.rollout([sims[0], sims[0]], 3),
         r"^rollout: simulations\[1\] is simulations\[0\]"),
        (lambda: ecpsim.rollout([sims[0], pushes[0]], 3),
         r"^rollout: simulations\[1\] \(.*push_box.yaml\) has 2 bodies, simulations\[0\] "
         r"\(.*slide.yaml\) 1"),
        (lambda: ecpsim.rollout(sims, 3, controls=np.zeros((2, 3, 1, 3))),
         r"^rollout: controls of shape \(2, 3, 1, 3\): expected .* shape \(2, 3, 1, 6\)"),
        (lambda: ecpsim.rollout(sims, 3, controls=np.full((2, 3, 1, 6), np.nan)),
         r"^rollout: controls\[0, 0, 0\] \(body 'box' of simulation 0 on its step 1\) = \[nan"),
        (lambda: ecpsim.rollout(pushes, 3, controls=kinematic),
         r"^rollout: controls\[1, 2, 1\] \(body 'pusher' of simulation 1 on its step 3\) = "
         r"\[1, 0, 0, 0, 0, 0\]: a kinematic body: expected zeros"),
    ]
    for call, message in cases:
        with pytest.raises(ecpsim.InputError, match=message):
            call()
    assert all(sim.steps == 0 for sim in sims + pushes)


def test_a_failing_simulation_stops_and_the_others_finish(scenes):
    # one Newton iteration cannot solve the tilted box's first contact step (test_simulation.py)
    slide = ecpsim.load_scene(str(scenes / "slide.yaml"))
    failing = ecpsim.load_scene(str(scenes / "tilted_box.yaml"), {"solver.max_iterations": 1})
    reference = ecpsim.Simulation(failing)
    good_steps = 0
    with pytest.raises(ecpsim.SolverFailure) as alone_error:
        for good_steps in range(100):
            reference.step()
    steps = good_steps + 10

    sims = [ecpsim.Simulation(slide), ecpsim.Simulation(failing), ecpsim.Simulation(slide),
            ecpsim.Simulation(failing)]
    with pytest.raises(ecpsim.SolverFailure) as error:
        ecpsim.rollout(sims, steps, threads=2)
    e = error.value
    message = str(e)
    assert message.startswith(
        f"rollout: simulation 1 failed in its step {good_steps + 1} of {steps} (it keeps its "
        f"state after {good_steps} good steps, t = ")
    assert str(alone_error.value) in message
    assert f"simulations 3 (step {good_steps + 1}) failed too" in message
    assert "the other 2 of 4 took all" in message
    assert e.simulation == 1 and e.steps_done == good_steps
    assert [(i, k) for i, k, _ in e.failures] == [(1, good_steps), (3, good_steps)]
    assert e.failures[0][2] == str(alone_error.value)
    # the failed simulations at their last good state, the others at the end
    for i in (1, 3):
        assert sims[i].steps == good_steps
        np.testing.assert_array_equal(sims[i].positions, reference.positions)
        assert not sims[i].last_report["converged"]
    assert sims[0].steps == sims[2].steps == steps
    # the completed simulations' rows, and never a NaN
    results = e.results
    np.testing.assert_array_equal(results["simulations"], [0, 2])
    expected = alone(ecpsim.Simulation(slide), steps)
    for j in range(2):
        assert_rows_equal(results, j, expected, f"completed {j}")
    for key in FIELDS + ("time",):
        assert results[key].shape[:2] == (2, steps) and np.isfinite(results[key]).all()


# ---- domain randomization ---------------------------------------------------------------------


def poses(sim, steps):
    """(steps, n, 7): the positions and quaternions after each of `steps` steps."""
    rows = alone(sim, steps)
    return np.concatenate([rows["positions"], rows["quaternions"]], axis=2)


def test_set_mass_equals_the_mass_override(scenes):
    # 2× the mass scales the inertia by exactly 2, the loader's 30 · unit inertia to the bit; the
    # tilted box turns as it lands, so its inertia matters
    for name, mass in (("slide.yaml", 15), ("tilted_box.yaml", 5)):
        scene = ecpsim.load_scene(str(scenes / name))
        sim = ecpsim.Simulation(scene)
        sim.set_mass("box", 2 * mass)
        heavy = ecpsim.Simulation(ecpsim.load_scene(str(scenes / name),
                                                    {"bodies.0.mass": 2 * mass}))
        np.testing.assert_array_equal(poses(sim, 40), poses(heavy, 40), err_msg=name)
        # the Scene stays as loaded, and so does another Simulation of it
        assert scene.bodies[0]["mass"] == mass
        np.testing.assert_array_equal(poses(ecpsim.Simulation(scene), 40),
                                      poses(ecpsim.Simulation(ecpsim.load_scene(
                                          str(scenes / name))), 40))


def test_set_inertia_and_set_mass_with_inertia_equal_their_overrides(scenes):
    path = str(scenes / "tilted_box.yaml")
    inertia = [[0.05, 0.001, 0], [0.001, 0.04, 0], [0, 0, 0.06]]
    sim = ecpsim.Simulation(ecpsim.load_scene(path))
    sim.set_inertia(0, inertia)
    loaded = ecpsim.Simulation(ecpsim.load_scene(
        path, {"bodies.0.inertia": np.ravel(inertia).tolist()}))
    np.testing.assert_array_equal(poses(sim, 40), poses(loaded, 40))
    sim = ecpsim.Simulation(ecpsim.load_scene(path))
    sim.set_mass(0, 7, inertia=[0.05, 0.04, 0.06])
    loaded = ecpsim.Simulation(ecpsim.load_scene(
        path, {"bodies.0.mass": 7, "bodies.0.inertia": [0.05, 0.04, 0.06]}))
    np.testing.assert_array_equal(poses(sim, 40), poses(loaded, 40))


def test_set_friction_equals_the_friction_override(scenes):
    path = str(scenes / "slide.yaml")
    assert ecpsim.load_scene(path).contact_names == ["box.ground"]
    for contact in ("box.ground", 0):
        sim = ecpsim.Simulation(ecpsim.load_scene(path))
        sim.set_friction(contact, mu=0.3, e_r=0.05)
        loaded = ecpsim.Simulation(ecpsim.load_scene(
            path, {"ground.friction.mu": 0.3, "ground.friction.e_r": 0.05}))
        np.testing.assert_array_equal(poses(sim, 30), poses(loaded, 30))
        assert sim.contacts()[0]["friction"] == {"mu": 0.3, "e_t": 1, "e_o": 1, "e_r": 0.05}
    # a contact between bodies, by name
    push = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    names = push.scene.contact_names
    k = names.index("box.pusher")
    push.set_friction("box.pusher", mu=0.05)
    assert push.contacts()[k]["friction"]["mu"] == 0.05
    # e_r: patch, as the override of the same key
    sim = ecpsim.Simulation(ecpsim.load_scene(path))
    sim.set_friction("box.ground", e_r="patch")
    loaded = ecpsim.Simulation(ecpsim.load_scene(path, {"ground.friction.e_r": "patch"}))
    np.testing.assert_array_equal(poses(sim, 30), poses(loaded, 30))
    assert sim.contacts()[0]["friction"]["e_r"] == "patch"
    with pytest.raises(ecpsim.InputError, match=r"^set_friction: e_r = 'pach': expected a length"):
        sim.set_friction("box.ground", e_r="pach")


def test_bad_values_raise_the_loaders_message_and_change_nothing(scenes):
    path = str(scenes / "tilted_box.yaml")
    sim = ecpsim.Simulation(ecpsim.load_scene(path))
    cases = [
        (lambda: sim.set_mass("box", -1),
         r"^set_mass\(body 'box'\): bodies\[0\]\.mass = -1: expected a mass of body \"box\""),
        (lambda: sim.set_mass("box", float("nan")), r"^set_mass\(body 'box'\): bodies\[0\]\.mass"),
        (lambda: sim.set_mass("box", 5, inertia=[1, 1, 3]),
         r"^set_mass\(body 'box'\): bodies\[0\]\.inertia = .*each principal moment <= the sum"),
        (lambda: sim.set_inertia("box", [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]),
         r"^set_inertia\(body 'box'\): bodies\[0\]\.inertia = .*symmetric"),
        (lambda: sim.set_inertia("box", [1, 2]),
         r"^set_inertia: inertia = \[1, 2\]: expected 3 principal moments"),
        (lambda: sim.set_mass("lid", 1), r"^set_mass: body = 'lid': expected a body name \(box\)"),
        (lambda: sim.set_friction("box.ground", mu=-0.1),
         r"^set_friction\(contact 'box\.ground'\): contacts\[0\]\.friction\.mu = -0\.1: "
         r"expected a friction coefficient >= 0"),
        (lambda: sim.set_friction(0, mu=0.5, e_r=0),
         r"^set_friction\(contact 'box\.ground'\): contacts\[0\]\.friction\.e_r = 0: expected a "
         r"torsional ellipsoid semi-axis > 0 m"),
        (lambda: sim.set_friction("box.floor", mu=0.5),
         r"^set_friction: contact = 'box\.floor': expected a contact name of "
         r"Scene\.contact_names \(box\.ground\)"),
    ]
    for call, message in cases:
        with pytest.raises(ecpsim.InputError, match=message):
            call()
    # the refused values left nothing behind (set_friction(0, mu=0.5, e_r=0) not even its mu)
    assert sim.contacts()[0]["friction"]["mu"] == 0.22
    np.testing.assert_array_equal(poses(sim, 30),
                                  poses(ecpsim.Simulation(ecpsim.load_scene(path)), 30))
    push = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    with pytest.raises(ecpsim.InputError, match=r"^set_mass\(body 'pusher'\): a kinematic body"):
        push.set_mass("pusher", 2)


def test_reset_restores_the_scenes_values(scenes):
    path = str(scenes / "tilted_box.yaml")
    sim = ecpsim.Simulation(ecpsim.load_scene(path))
    sim.set_mass(0, 9)
    sim.set_friction(0, mu=0.6)
    sim.step(5)
    sim.reset()
    assert sim.contacts()[0]["friction"]["mu"] == 0.22
    np.testing.assert_array_equal(poses(sim, 30),
                                  poses(ecpsim.Simulation(ecpsim.load_scene(path)), 30))


def test_randomized_simulations_roll_out_as_stepped_alone(scenes):
    # the use the two parts serve together: a batch of one scene with drawn masses and friction
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"))
    rng = np.random.default_rng(4)
    draws = [(rng.uniform(5, 30), rng.uniform(0.1, 0.5)) for _ in range(4)]

    def batch():
        sims = [ecpsim.Simulation(scene) for _ in draws]
        for sim, (mass, mu) in zip(sims, draws):
            sim.set_mass(0, mass)
            sim.set_friction(0, mu=mu)
        return sims

    result = ecpsim.rollout(batch(), 30, threads=2)
    for i, sim in enumerate(batch()):
        assert_rows_equal(result, i, alone(sim, 30), f"draw {i}")
