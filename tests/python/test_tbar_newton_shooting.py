"""examples/tbar_newton_shooting.py: Gauss–Newton on the T-bar's constant wrench with the chained
step Jacobians converges to the goal pose, quadratically once close."""

import math

import numpy as np

import tbar_newton_shooting as shooting

GOAL = (0.06, 0.03, math.radians(100))  # m, m, rad: from (0, 0, 90°), the example's default
STEPS = 50                              # 0.5 s
# the goal error must fall by this factor within the iterations: Newton's quadratic convergence
# takes 7.9e-2 m to 1e-10 m in four (measured), so 1e6 leaves margin for round-off
REDUCTION = 1e6
ITERATIONS = 5
# relative: the chained A, B against central differences of whole rollouts, at a force step of
# 1e-6 N (the rollouts' noise ~1e-13 m over the 0.05 m path gives ~1e-7)
CHAIN_AGREEMENT = 1e-5


def test_the_goal_error_falls_by_the_stated_factor():
    wrenches, errors, flags = shooting.shoot(GOAL, STEPS, ITERATIONS)
    print(errors)
    assert errors[0] > 0.05
    assert errors[-1] <= errors[0] / REDUCTION
    # quadratic once close: the step from 1e-3 m takes it below 1e-5 m
    close = next(k for k, e in enumerate(errors) if e < 2e-3)
    assert errors[close + 1] < 1e-2 * errors[close]
    # every step's Jacobians were those of an isolated, non-degenerate root (the T slides flat)
    assert all(d == 0 and s == 0 for d, s in flags)


def test_the_chained_jacobians_match_whole_rollouts():
    scene = shooting.tbar_scene(duration=STEPS * 0.01)
    u = np.array([4.6, 2.4, 0.17])
    S = shooting.roll_out(scene, u, GOAL, STEPS).sensitivity
    rows = list(shooting.POSE_ROWS)
    for k, column in enumerate(shooting.WRENCH_COLUMNS):
        eps = 1e-6 if k < 2 else 1e-7  # N, N·m
        e = np.eye(3)[k] * eps
        plus = shooting.roll_out(scene, u + e, GOAL, STEPS, with_jacobians=False).error
        minus = shooting.roll_out(scene, u - e, GOAL, STEPS, with_jacobians=False).error
        fd = -(plus - minus) / (2 * eps)  # error = goal − pose
        assert np.abs(S[rows, column] - fd).max() <= CHAIN_AGREEMENT * np.abs(fd).max()
