"""Gauss–Newton single shooting with the step Jacobians: the constant wrench (a force at the CM
in the table's plane and a torque about z) that, held over N steps, brings the T-bar of
scenes/tbar.yaml (without its loads, lying on the table) to a goal pose (x, y, yaw) at step N.

    PYTHONPATH=build/python /usr/bin/python3 examples/tbar_newton_shooting.py \\
        [--goal X Y YAW_DEG] [--steps N] [--iterations K]

Each iteration rolls the T out over the N steps with the current wrench u and, at every step,
takes A_k, B_k = sim.step_jacobians() (with u pending, so the derivatives are those of the step
taken), chaining the sensitivity of the state to u, S_{k+1} = A_k S_k + B_k (S_0 = 0: u does not
change the start). The goal's residual r = goal − (x, y, yaw)(x_N) then has the Jacobian
−S_N[(x, y, θ_z), (F_x, F_y, τ_z)] (a turn θ_z about the vertical changes the yaw of a flat body
by θ_z, to first order), and the Gauss–Newton step δu = S⁺ r is taken, halved until the
goal error falls (the pose is not smooth where the T would stick: a step that leaves the wrench
inside the friction ellipsoid stops it). Prints the goal error per iteration.

Exit codes as the CLI's: 0 ok, 1 bad input, 3 solver failure, 5 model invalid.
"""

import argparse
import dataclasses
import math
import sys

import numpy as np

import ecpsim
from tbar_closed_loop import tbar_scene, wrapped, yaw_of

# rows of a body's 12 state coordinates (p, θ, v, ω) and columns of its 6 inputs (F, τ) the
# shooting uses: the pose in the table's plane and the planar wrench
POSE_ROWS = (0, 1, 5)       # p_x, p_y, θ_z
WRENCH_COLUMNS = (0, 1, 5)  # F_x, F_y, τ_z
# line search: halvings of a Gauss–Newton step before giving up the iteration
MAX_HALVINGS = 12


@dataclasses.dataclass
class Rollout:
    error: np.ndarray        # (3,) goal − pose at step N: x, y (m), yaw (rad)
    sensitivity: np.ndarray  # (12, 6) ∂x_N/∂u, from the chained step Jacobians
    degenerate_steps: int    # steps whose Jacobians flagged a degenerate contact mode
    singular_steps: int      # steps whose solution was not isolated


def roll_out(scene, wrench, goal, steps, with_jacobians=True):
    """The T held under `wrench` = (F_x, F_y, τ_z) for `steps` steps from the scene's start."""
    sim = ecpsim.Simulation(scene)
    force = [wrench[0], wrench[1], 0.0]
    torque = [0.0, 0.0, wrench[2]]
    S = np.zeros((12, 6))
    degenerate = singular = 0
    for _ in range(steps):
        sim.apply_wrench("tbar", force=force, torque=torque)
        if with_jacobians:
            J = sim.step_jacobians()
            A, B = J
            S = A @ S + B
            degenerate += J.flags["degenerate"]
            singular += not J.flags["isolated"]
        sim.step()
    error = np.append(np.asarray(goal[:2]) - sim.positions[0, :2],
                      wrapped(goal[2] - yaw_of(sim.quaternions[0])))
    return Rollout(error, S, degenerate, singular)


def goal_norm(error, length):
    """The goal error as one number: the position error and the yaw error times the T's length."""
    return math.hypot(np.linalg.norm(error[:2]), error[2] * length)


def shoot(goal, steps=50, iterations=6, wrench0=None):
    """Gauss–Newton iterations on the constant wrench; returns the wrenches and goal errors
    (m, yaw weighted by the T's radius of gyration) per iteration, the first the start's."""
    scene = tbar_scene(duration=steps * 0.01)
    body = scene.bodies[0]
    m = body["mass"]
    length = math.sqrt(np.trace(body["inertia"]) / m)
    if wrench0 is None:
        # a push above the friction μ m g towards the goal, no torque
        mu = scene.bodies[0]["friction"]["mu"]
        direction = np.asarray(goal[:2]) - np.asarray(body["position"][:2])
        direction /= np.linalg.norm(direction)
        wrench0 = np.append(1.5 * mu * m * np.linalg.norm(scene.gravity) * direction, 0.0)
    u = np.asarray(wrench0, float)
    rollout = roll_out(scene, u, goal, steps)
    wrenches, errors = [u.copy()], [goal_norm(rollout.error, length)]
    flags = [(rollout.degenerate_steps, rollout.singular_steps)]
    for _ in range(iterations):
        G = -rollout.sensitivity[np.ix_(POSE_ROWS, WRENCH_COLUMNS)]  # ∂error/∂u
        step = -np.linalg.lstsq(G, rollout.error, rcond=None)[0]
        for _ in range(MAX_HALVINGS):
            trial = roll_out(scene, u + step, goal, steps)
            if goal_norm(trial.error, length) < errors[-1]:
                break
            step /= 2
        else:
            break  # no descent along the Gauss–Newton direction: converged as far as it goes
        u, rollout = u + step, trial
        wrenches.append(u.copy())
        errors.append(goal_norm(rollout.error, length))
        flags.append((rollout.degenerate_steps, rollout.singular_steps))
    return wrenches, errors, flags


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--goal", type=float, nargs=3, default=(0.06, 0.03, 100.0),
                        metavar=("X", "Y", "YAW_DEG"), help="m, m, degrees (start: 0, 0, 90°)")
    parser.add_argument("--steps", type=int, default=50, help="N steps of 0.01 s")
    parser.add_argument("--iterations", type=int, default=6)
    args = parser.parse_args(argv)
    goal = (args.goal[0], args.goal[1], math.radians(args.goal[2]))
    try:
        wrenches, errors, flags = shoot(goal, args.steps, args.iterations)
    except ecpsim.InputError as e:
        print(e, file=sys.stderr)
        return 1
    except ecpsim.SolverFailure as e:
        print(e, file=sys.stderr)
        return 3
    except ecpsim.ModelInvalid as e:
        print(e, file=sys.stderr)
        return 5
    for k, (u, e, (degenerate, singular)) in enumerate(zip(wrenches, errors, flags)):
        print(f"iteration {k}: F = ({u[0]:.6f}, {u[1]:.6f}) N, tau_z = {u[2]:.6f} N m, "
              f"goal error {e:.3e} m (degenerate steps {degenerate}, not isolated {singular})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
