"""Simulation: stepping, state arrays, save/restore, apply_wrench, kinematic and gripper targets, contacts
and errors, checked against closed forms and against the engine's own scene loads."""

import numpy as np
import pytest

import ecpsim

# m/s: implicit Euler with a constant Coulomb deceleration reproduces v0 − μ g t to round-off
# and the solver's tolerance (as tests/engine/time_step_test.cpp)
SLIDE_VELOCITY_TOL = 1e-9
# relative: a converged normal impulse is m g h up to the solver tolerance 1e-12 (unscaled)
FORCE_REL_TOL = 1e-9
# m: a point given in world coordinates returns to the body frame through R^T (p + R r − p):
# a few ulps of the box's 0.5 m size
POINT_ROUNDOFF_TOL = 1e-14
# m: a box held by sticking pads creeps at most 1e-5 of the jaws' drive (h F / m = 1 m/s in
# scenes/gripper.yaml) for the 0.2 s of a drag (engine/README.md, "Grippers")
GRIP_CREEP_TOL = 2e-6
# a few ulps of a quantity of size ≲ 1: a kinematic body's position at its target (m), the
# ground's unit normal
UNIT_ROUNDOFF_TOL = 1e-15
# relative: a kinematic body's velocity, (target − start) / h, a 2 mm difference of sub-metre
# coordinates (round-off ≈ 1e-13 of it)
TARGET_VELOCITY_REL_TOL = 1e-12
# m: a box resting on the table, to the solver's position error (1e-12 of its lengths) with margin
REST_HEIGHT_TOL = 1e-9

BOX_ON_GROUND = """\
h: 0.01
duration: 0.2
gravity: [0, 0, -9.8]
ground:
  friction: {mu: 0.3, e_t: 1, e_o: 1, e_r: 0.05}
bodies:
  - name: box
    shape: {box: {size: [0.5, 0.4, 0.1]}}
    mass: 2
    position: [0, 0, 0.05]
"""


def test_slide_follows_the_closed_form(scenes):
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"))
    sim = ecpsim.Simulation(scene)
    mu, g, v0 = 0.22, 9.8, 0.5
    t_star = v0 / (mu * g)
    assert sim.body_names == ["box"]
    for _ in range(40):
        sim.step()
        assert sim.last_report["converged"] and sim.last_report["failure"] is None
        expected = max(0.0, v0 - mu * g * sim.time)
        assert sim.velocities[0, 0] == pytest.approx(expected, abs=SLIDE_VELOCITY_TOL)
        assert sim.velocities.shape == (1, 3)
        assert sim.quaternions.shape == (1, 4)
        contact = sim.contacts()[0]
        # flat on the ground: the normal force carries the weight; sliding, friction is μ m g
        m = 15
        assert contact["f_n"] == pytest.approx(m * g, rel=FORCE_REL_TOL)
        if sim.time < t_star - scene.h:
            assert contact["mode"] == "sliding"
            assert contact["force"][0] == pytest.approx(-mu * m * g, rel=FORCE_REL_TOL)
        elif sim.time > t_star + scene.h:
            assert contact["mode"] == "sticking"
        # model: auto (the default) steps a box flat on the ground with the planar model
        assert contact["model"] == "planar"
        assert sim.last_report["models"] == {"box": "planar"}
        assert contact["body"] == "box" and contact["other"] == "ground"
    assert sim.time == 40 * scene.h
    assert sim.steps == 40


def test_step_n_equals_n_single_steps(scenes):
    scene = ecpsim.load_scene(str(scenes / "tbar.yaml"))
    one, many = ecpsim.Simulation(scene), ecpsim.Simulation(scene)
    for _ in range(25):
        one.step()
    many.step(25)
    np.testing.assert_array_equal(one.positions, many.positions)
    np.testing.assert_array_equal(one.quaternions, many.quaternions)


def test_save_and_restore_continue_bit_for_bit(scenes):
    scene = ecpsim.load_scene(str(scenes / "tbar.yaml"))
    sim = ecpsim.Simulation(scene)
    sim.step(20)
    saved = sim.get_state()
    assert saved.time == sim.time and saved.steps == 20
    sim.step(30)
    first = (sim.positions, sim.quaternions, sim.velocities, sim.angular_velocities,
             [c["p_n"] for c in sim.contacts()])
    sim.set_state(saved)
    assert sim.time == saved.time
    sim.step(30)
    again = (sim.positions, sim.quaternions, sim.velocities, sim.angular_velocities,
             [c["p_n"] for c in sim.contacts()])
    for a, b in zip(first, again):
        np.testing.assert_array_equal(a, b)
    # another Simulation of the same scene continues from it alike
    other = ecpsim.Simulation(scene)
    other.set_state(saved)
    other.step(30)
    np.testing.assert_array_equal(other.positions, first[0])
    # reset goes back to t = 0 and the same trajectory
    sim.reset()
    assert sim.time == 0
    sim.step(50)
    np.testing.assert_array_equal(sim.positions, first[0])


def test_set_state_of_another_scene_is_refused(scenes):
    slide = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    push = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    with pytest.raises(ecpsim.InputError, match="expected one of this scene"):
        slide.set_state(push.get_state())


def scene_with_loads(tmp_path, loads):
    path = tmp_path / "loaded.yaml"
    path.write_text(BOX_ON_GROUND + "loads:\n" + loads)
    return ecpsim.load_scene(str(path))


def test_apply_wrench_equals_a_scene_load(tmp_path):
    # a push through the CM and a twist, in the first step only, as loads of window [0, h)
    loaded = scene_with_loads(tmp_path, (
        "  - {body: box, force: [12, -3, 0], end: 0.01}\n"
        "  - {body: box, torque: [0, 0, 1.5], end: 0.01}\n"))
    plain = ecpsim.load_scene(str(tmp_path / "loaded.yaml"), {"loads": []})
    reference, controlled = ecpsim.Simulation(loaded), ecpsim.Simulation(plain)
    controlled.apply_wrench("box", force=[12, -3, 0], torque=[0, 0, 1.5])
    for _ in range(15):
        reference.step()
        controlled.step()
        # the same applied impulse in the same MNCP: bit-identical
        np.testing.assert_array_equal(reference.positions, controlled.positions)
        np.testing.assert_array_equal(reference.quaternions, controlled.quaternions)
        np.testing.assert_array_equal(reference.velocities, controlled.velocities)
    assert np.linalg.norm(controlled.velocities[0]) > 0


def test_apply_wrench_at_a_point_equals_a_scene_load_at_it(tmp_path):
    # a force at the box's corner region every step: moves and turns it
    loaded = scene_with_loads(tmp_path, "  - {body: box, force: [0, 8, 0], at: [0.2, 0, 0]}\n")
    plain = ecpsim.load_scene(str(tmp_path / "loaded.yaml"), {"loads": []})
    reference, controlled = ecpsim.Simulation(loaded), ecpsim.Simulation(plain)
    for _ in range(10):
        # the point fixed in the body, given in world coordinates at the step's start
        q = controlled.quaternions[0]
        w, v = q[0], q[1:]
        r = np.array([0.2, 0, 0])
        rotated = r + 2 * np.cross(v, np.cross(v, r) + w * r)
        controlled.apply_wrench(0, force=(0, 8, 0), at=controlled.positions[0] + rotated)
        reference.step()
        controlled.step()
        np.testing.assert_allclose(controlled.positions, reference.positions, rtol=0,
                                   atol=POINT_ROUNDOFF_TOL)
    assert abs(controlled.angular_velocities[0, 2]) > 0


def test_apply_wrench_checks_its_input(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "push_box.yaml")))
    with pytest.raises(ecpsim.InputError, match="kinematic"):
        sim.apply_wrench("pusher", force=[1, 0, 0])
    with pytest.raises(ecpsim.InputError, match="body = 'nobody'.*box, pusher"):
        sim.apply_wrench("nobody", force=[1, 0, 0])
    with pytest.raises(ecpsim.InputError, match="force = .*nan.*expected a finite number"):
        sim.apply_wrench("box", force=[float("nan"), 0, 0])
    with pytest.raises(ecpsim.InputError, match="expected 3 numbers"):
        sim.apply_wrench("box", force=[1, 0])


def test_kinematic_target_moves_the_pusher_at_constant_speed(scenes):
    scene = ecpsim.load_scene(str(scenes / "push_box.yaml"))
    sim = ecpsim.Simulation(scene)
    pusher = sim.body_names.index("pusher")
    start = sim.positions[pusher].copy()
    step = np.array([0.002, 0, 0])  # m per step: 0.2 m/s
    for k in range(1, 6):
        sim.set_kinematic_target("pusher", start + k * step)
        sim.step()
        np.testing.assert_allclose(sim.positions[pusher], start + k * step, rtol=0,
                                   atol=UNIT_ROUNDOFF_TOL)
        np.testing.assert_allclose(sim.velocities[pusher], step / scene.h,
                                   rtol=TARGET_VELOCITY_REL_TOL)
    # without a new target it stays
    sim.step()
    np.testing.assert_allclose(sim.positions[pusher], start + 5 * step, rtol=0,
                               atol=UNIT_ROUNDOFF_TOL)
    with pytest.raises(ecpsim.InputError, match="dynamic body"):
        sim.set_kinematic_target("box", [0, 0, 0])
    sim.reset()
    np.testing.assert_array_equal(sim.positions[pusher], start)


def test_a_gripper_driven_step_by_step_drags_what_it_holds(scenes):
    # scenes/gripper.yaml's hand closes on the box with 5 N by 0.5 s; from there the controller
    # drags the frame 1 mm per step along +y, then lets go (force 0) and lifts the frame
    scene = ecpsim.load_scene(str(scenes / "gripper.yaml"))
    assert scene.grippers == [{"name": "hand", "jaws": ("left_jaw", "right_jaw"),
                               "axis": pytest.approx([1, 0, 0]),
                               "force": "t < 0.3 ? 0.2 : (t < 2.6 ? 5 : 0)"}]
    sim = ecpsim.Simulation(scene)
    sim.step(50)
    box = sim.body_names.index("box")
    frame = np.array([0.0, 0.0, 0.04])
    for _ in range(20):
        frame += [0, 0.001, 0]
        sim.set_gripper_target("hand", frame)
        sim.step()
    # held: the box moved with the frame, up to the pads' sticking creep (1e-5 of the jaws'
    # 1 m/s drive, over 0.2 s: 2e-6 m)
    np.testing.assert_allclose(sim.positions[box][:2], [0, 0.02], atol=GRIP_CREEP_TOL)
    # released, the frame lifts and leaves the box on the table
    sim.set_gripper_target("hand", frame + [0, 0, 0.05], force=0)
    sim.step(10)
    assert sim.positions[box][2] == pytest.approx(0.04, abs=REST_HEIGHT_TOL)
    jaws = [sim.body_names.index(j) for j in ("left_jaw", "right_jaw")]
    # m: the jaws ride at the frame's height 0.04 + 0.05 m, to round-off
    jaw_height_tol = 1e-12
    assert all(sim.positions[j][2] == pytest.approx(0.09, abs=jaw_height_tol) for j in jaws)
    with pytest.raises(ecpsim.InputError, match="expected a closing force"):
        sim.set_gripper_target("hand", frame, force=-1)
    with pytest.raises(ecpsim.InputError, match=r"expected a gripper name \(hand\)"):
        sim.set_gripper_target("claw", frame)
    # reset() drops the targets and the force: the scene's grasp again, bit for bit
    sim.reset()
    sim.step(60)
    fresh = ecpsim.Simulation(scene)
    fresh.step(60)
    np.testing.assert_array_equal(sim.positions, fresh.positions)


def test_contact_modes_and_forces_through_a_fall(scenes):
    # the slide's box dropped from 0.1 m: separated, then landed
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"), {"bodies.0.position": [0, 0, 0.15],
                                                            "bodies.0.velocity": [0, 0, 0]})
    sim = ecpsim.Simulation(scene)
    sim.step()
    assert sim.contacts()[0]["mode"] == "separated"
    assert sim.contacts()[0]["f_n"] == 0
    sim.step(40)
    contact = sim.contacts()[0]
    assert contact["mode"] == "sticking"
    assert contact["f_n"] == pytest.approx(15 * 9.8, rel=FORCE_REL_TOL)
    np.testing.assert_allclose(contact["normal"], [0, 0, 1], atol=UNIT_ROUNDOFF_TOL)


def test_setting_arrays(scenes):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    sim.velocities = [[1.0, 0, 0]]
    np.testing.assert_array_equal(sim.velocities, [[1.0, 0, 0]])
    with pytest.raises(ecpsim.InputError, match=r"shape \(1, 3\)"):
        sim.positions = np.zeros((2, 3))
    with pytest.raises(ecpsim.InputError, match="finite number"):
        sim.velocities = [[np.inf, 0, 0]]


def test_solver_failure_names_time_body_and_residual(scenes):
    # one Newton iteration cannot solve the first contact step from a cold start (as the CLI test)
    scene = ecpsim.load_scene(str(scenes / "tilted_box.yaml"), {"solver.max_iterations": 1})
    sim = ecpsim.Simulation(scene)
    with pytest.raises(ecpsim.SolverFailure) as error:
        sim.step(100)
    message = str(error.value)
    assert "t = " in message and "'box'" in message and "residual" in message
    # the state is the last good one, finite
    assert np.all(np.isfinite(sim.positions))
    assert isinstance(error.value, RuntimeError)
    # the report is the failed step's, not the last good one's
    report = sim.last_report
    assert not report["converged"] and report["failure"] == message
    assert f"residual {report['residual']:.3g} > tolerance" in message and report["retries"] > 0


def test_poses_set_into_an_obstacle_or_a_body_are_refused(scenes):
    # the scene's check of initial poses holds for poses set later: 0.4 m into the ground, tilted
    # 45° about x (0.25 sin 45° + 0.05 cos 45° − 0.05 = 0.162 m), or a box inside the other, is an InputError naming the pair and the depth, and nothing changes
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    before = sim.positions
    with pytest.raises(ecpsim.InputError,
                       match=r"^positions: body 'box' is 0\.4 m inside obstacle 'ground'"):
        sim.positions = [[0, 0, -0.35]]
    np.testing.assert_array_equal(sim.positions, before)
    with pytest.raises(ecpsim.InputError, match=r"^quaternions: body 'box' is 0\.162 m inside"):
        sim.quaternions = [[np.cos(np.pi / 8), np.sin(np.pi / 8), 0, 0]]
    stack = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "stack.yaml")))
    state = stack.get_state()
    inside = stack.positions
    inside[1] = inside[0] + [0, 0, 0.01]
    with pytest.raises(ecpsim.InputError, match=r"^positions: body '\w+' is .* m inside body"):
        stack.positions = inside
    stack.step(5)
    stack.set_state(state)  # a state of the run is apart
    # the scene's allow_initial_penetration lets it through
    scene = ecpsim.load_scene(str(scenes / "slide.yaml"),
                              {"bodies.0.allow_initial_penetration": True})
    allowed = ecpsim.Simulation(scene)
    allowed.positions = [[0, 0, 0.04]]
    assert allowed.positions[0, 2] == 0.04


def test_model_invalid(scenes):
    # the planar model needs the body flat on the ground; the tilted box is not
    scene = ecpsim.load_scene(str(scenes / "tilted_box.yaml"), {"model": "planar"})
    with pytest.raises(ecpsim.ModelInvalid):
        ecpsim.Simulation(scene).step(100)
