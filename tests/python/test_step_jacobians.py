"""Simulation.step_jacobians() against central finite differences of whole steps.

Each state coordinate is perturbed by ±ε (rotations by a turn in the world frame, q = exp(θ) q₀),
the simulation stepped once from it, and the resulting states differenced; inputs by a wrench
±ε at the CM applied with apply_wrench. Agreement is measured in each quantity's natural scale
(natural_scales): the largest entry of |A - A_fd| with rows divided and columns multiplied by the
scales, relative to the largest scaled entry of A_fd (at least 1: A holds identity blocks).
"""

import numpy as np
import pytest

import ecpsim

# the finite differences' step as a fraction of each coordinate's scale: the steps' solutions
# carry ~1e-13 of their scales in noise, which 1e-6 turns into ~1e-7 of error, against a
# truncation error of ~1e-12; and 1e-6 of a body's length keeps a body lowered onto the ground
# within the positions setter's overlap check (1e-6 of its size)
STEP_FRACTION = 1e-6
# the same where bodies touch bodies: their sticking contacts creep (a viscous law up to 1e-5 of
# the velocity scale V, engine/README.md), and a perturbation of 1e-6 already slides them (the
# grasp's box lowered by 4e-8 m is pushed out at 4e-6 m/s, above the pads' creep); at 1e-8 the
# mode stays and the noise still gives ~1e-6
COUPLED_STEP_FRACTION = 1e-8
# the agreement asserted where the contact mode is stable (scaled, relative)
AGREEMENT = 1e-5


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def qexp(theta):
    angle = np.linalg.norm(theta)
    if angle == 0:
        return np.array([1.0, 0, 0, 0])
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * theta / angle])


def qlog(q):
    q = q if q[0] >= 0 else -q
    s = np.linalg.norm(q[1:])
    return 2 * np.arctan2(s, q[0]) * q[1:] / s if s > 0 else np.zeros(3)


def conj(q):
    return np.array([q[0], -q[1], -q[2], -q[3]])


def natural_scales(sim, names):
    """Per body: state [L, 1 rad, V, V/L] and input [m V / h, m V L / h], with L the radius of
    gyration and V = max(|v| + |ω| L, g h)."""
    scene = sim.scene
    h, g = scene.h, np.linalg.norm(scene.gravity)
    state, inputs = [], []
    for name in names:
        i = sim.body_names.index(name)
        body = scene.bodies[i]
        m = body["mass"]
        L = np.sqrt(np.trace(body["inertia"]) / m)
        V = max(np.linalg.norm(sim.velocities[i]) + np.linalg.norm(sim.angular_velocities[i]) * L,
                g * h)
        state += [L] * 3 + [1.0] * 3 + [V] * 3 + [V / L] * 3
        inputs += [m * V / h] * 3 + [m * V * L / h] * 3
    return np.array(state), np.array(inputs)


def state_after_step(sim, saved, names, edit=None, wrench=None):
    """The state x⁺ (positions, quaternions, velocities, angular velocities) of `names` after one
    step from `saved`, with `edit(sim)` applied to the state and `wrench` = (body, force, torque)
    applied before it."""
    sim.set_state(saved)
    if edit is not None:
        edit(sim)
    if wrench is not None:
        sim.apply_wrench(wrench[0], force=wrench[1], torque=wrench[2])
    sim.step()
    rows = [sim.body_names.index(n) for n in names]
    return (sim.positions[rows], sim.quaternions[rows], sim.velocities[rows],
            sim.angular_velocities[rows])


def difference(a, b):
    """a − b in the 12 coordinates per body (rotation: log(q_a q_b⁻¹), world frame)."""
    out = []
    for i in range(len(a[0])):
        out += list(a[0][i] - b[0][i]) + list(qlog(qmul(a[1][i], conj(b[1][i])))) \
            + list(a[2][i] - b[2][i]) + list(a[3][i] - b[3][i])
    return np.array(out)


def finite_differences(sim, names, fraction=STEP_FRACTION):
    saved = sim.get_state()
    sx, su = natural_scales(sim, names)
    nominal = state_after_step(sim, saved, names)
    n = len(names)
    A = np.zeros((12 * n, 12 * n))
    B = np.zeros((12 * n, 6 * n))
    for col in range(12 * n):
        i = sim.body_names.index(names[col // 12])
        part, axis = (col % 12) // 3, col % 3
        eps = fraction * sx[col]
        diffs = []
        for sign in (1, -1):
            e = np.zeros(3)
            e[axis] = sign * eps

            def edit(s, e=e):
                field = ("positions", "quaternions", "velocities", "angular_velocities")[part]
                values = getattr(s, field)
                if part == 1:
                    values[i] = qmul(qexp(e), values[i])
                else:
                    values[i] += e
                setattr(s, field, values)
            diffs.append(difference(state_after_step(sim, saved, names, edit=edit), nominal))
        A[:, col] = (diffs[0] - diffs[1]) / (2 * eps)
    for col in range(6 * n):
        eps = fraction * su[col]
        diffs = []
        for sign in (1, -1):
            e = np.zeros(3)
            e[col % 3] = sign * eps
            zero = np.zeros(3)
            wrench = (names[col // 6], e, zero) if col % 6 < 3 else (names[col // 6], zero, e)
            diffs.append(difference(state_after_step(sim, saved, names, wrench=wrench), nominal))
        B[:, col] = (diffs[0] - diffs[1]) / (2 * eps)
    sim.set_state(saved)
    return A, B


def scaled_error(M, M_fd, rows, cols):
    diff = (M - M_fd) / rows[:, None] * cols[None, :]
    ref = M_fd / rows[:, None] * cols[None, :]
    return np.abs(diff).max() / max(1.0, np.abs(ref).max())


def compare(sim, fraction=STEP_FRACTION, columns=None):
    """(A error, B error, jacobians), the errors over A's columns `columns` (all if None)."""
    J = sim.step_jacobians()
    A, B = J
    names = J.bodies
    sx, su = natural_scales(sim, names)
    A_fd, B_fd = finite_differences(sim, names, fraction)
    cols = np.ones(A.shape[1], bool) if columns is None else columns
    ea = scaled_error(A[:, cols], A_fd[:, cols], sx, sx[cols])
    eb = scaled_error(B, B_fd, sx, su)
    print(f"A error {ea:.2e}, B error {eb:.2e}, method {J.flags['method']}, islands "
          f"{J.flags['islands']}")
    return ea, eb, J


def loaded(scenes, name, steps):
    sim = ecpsim.Simulation(ecpsim.load_scene(str(scenes / name)))
    sim.step(steps)
    return sim


def test_the_result_unpacks_and_leaves_the_simulation_where_it_was(scenes):
    sim = loaded(scenes, "slide.yaml", 3)
    before = sim.get_state()
    J = sim.step_jacobians()
    A, B = J
    assert A.shape == (12, 12) and B.shape == (12, 6)
    assert J.bodies == ["box"]
    assert set(J.flags) >= {"degenerate", "isolated", "method", "residual", "islands"}
    assert sim.steps == before.steps
    assert np.array_equal(sim.positions, before.positions)


def test_pending_wrenches_are_part_of_the_point_and_stay_pending(scenes):
    # the linearization is the step step() takes next: with the pending wrench, which it leaves
    # pending (the step after it is bit-identical to one without the call)
    sim, other = loaded(scenes, "slide.yaml", 3), loaded(scenes, "slide.yaml", 3)
    for s in (sim, other):
        s.apply_wrench("box", force=[40.0, 0, 0])
    J = sim.step_jacobians()
    sim.step()
    other.step()
    assert np.array_equal(sim.velocities, other.velocities)
    # 40 N beats the friction μ m g = 32 N: the box speeds up, and a force along its slip
    # changes v⁺ by h/m per newton
    A, B = J
    assert B[6, 0] == pytest.approx(sim.scene.h / sim.scene.bodies[0]["mass"], rel=1e-9)


def test_a_sliding_box(scenes):
    sim = loaded(scenes, "slide.yaml", 5)  # sliding at 0.39 m/s
    ea, eb, J = compare(sim)
    assert not J.flags["degenerate"] and J.flags["isolated"]
    assert J.flags["method"] == "implicit_function"
    assert ea < AGREEMENT and eb < AGREEMENT
    # a horizontal force changes the next velocity by h/m per newton, as the closed form of a
    # slide at constant friction says (the friction's direction does not change along x)
    h, m = sim.scene.h, sim.scene.bodies[0]["mass"]
    A, B = J
    assert B[6, 0] == pytest.approx(h / m, rel=1e-9)


def test_a_spinning_box(scenes):
    tree = {"h": 0.01, "duration": 1,
            "ground": {"friction": {"mu": 0.3, "e_t": 1, "e_o": 1, "e_r": 0.1}},
            "bodies": [{"name": "box", "shape": {"box": {"size": [0.3, 0.2, 0.1]}}, "mass": 2,
                        "position": [0, 0, 0.05], "velocity": [0.2, 0.1, 0],
                        "angular_velocity": [0, 0, 4]}]}
    sim = ecpsim.Simulation(ecpsim.make_scene(tree))
    sim.step(3)
    ea, eb, J = compare(sim)
    assert not J.flags["degenerate"] and J.flags["isolated"]
    assert ea < AGREEMENT and eb < AGREEMENT


def test_a_box_tipping_over_its_edge(scenes):
    sim = loaded(scenes, "tilted_box.yaml", 10)  # rotating about its low edge
    ea, eb, J = compare(sim)
    assert J.flags["isolated"]
    assert ea < AGREEMENT and eb < AGREEMENT


def test_the_desk(scenes):
    sim = loaded(scenes, "desk.yaml", 20)  # sliding and turning on its four feet
    ea, eb, J = compare(sim)
    assert J.flags["isolated"]
    assert ea < AGREEMENT and eb < AGREEMENT


def test_a_push_by_a_kinematic_finger(scenes):
    sim = loaded(scenes, "push_box.yaml", 40)  # the pusher carrying the box since t = 0.1 s
    # the pusher's flat face: its ECP's height and the ground ECP's offset along the push carry
    # one moment between them, a set of solutions (one null direction of H, none of ν⁺)
    tilt_about_push = np.ones(12, bool)
    tilt_about_push[3] = False
    ea, eb, J = compare(sim, COUPLED_STEP_FRACTION, columns=tilt_about_push)
    assert not J.flags["isolated"]
    assert J.flags["method"] == "implicit_function_minimum_norm"
    island = J.flags["islands"][0]
    assert island["unknowns"] - island["rank"] == 1
    assert J.flags["A_determined"].all() and J.flags["B_determined"].all()
    # but a tilt about the push axis turns the box about the pusher's ECP, whose height the set
    # leaves free: the lateral slip there, and the creeping friction with it, depend on where
    # the solver lands on the set (the whole steps' differences wander from ε to ε), so that
    # column is left out
    assert ea < AGREEMENT and eb < AGREEMENT


def test_a_grasp(scenes):
    sim = loaded(scenes, "gripper.yaml", 80)  # held with 5 N, dragged along +y
    ea, eb, J = compare(sim, COUPLED_STEP_FRACTION)
    # where each pad's ECP sits on the box's face, and how the table and the pads share the
    # weight, is a set (three null directions of H); the motion is not on it
    assert not J.flags["isolated"]
    island = J.flags["islands"][0]
    assert island["bodies"] == ["box", "left_jaw", "right_jaw"]
    assert island["unknowns"] - island["rank"] == 3
    assert J.flags["A_determined"].all() and J.flags["B_determined"].all()
    assert ea < AGREEMENT and eb < AGREEMENT
