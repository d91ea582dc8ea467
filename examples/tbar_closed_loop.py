"""Closed-loop control from Python: a PD controller on the pose error (x, y, yaw) brings the T-bar
of scenes/tbar.yaml, lying on the table, to a goal pose through Simulation.apply_wrench, and
plots the pose error and the contact mode over time.

    PYTHONPATH=build/python /usr/bin/python3 examples/tbar_closed_loop.py \\
        [-o out/tbar_closed_loop] [--goal X Y YAW_DEG] [--duration S] [--omega RAD_PER_S]

The controller: every step it reads the pose and velocities and applies, for the next step, a
force at the CM F = kp e_xy − kd v_xy (saturated at --force-max, far below the push that would
tip the T) and a torque about z τ = kp_yaw e_yaw − kd_yaw ω_z (saturated at --torque-max). The
gains come from one natural frequency ω and damping ratio ζ per axis: kp = m ω², kd = 2 ζ m ω,
kp_yaw = I_zz ω², kd_yaw = 2 ζ I_zz ω.

Where it stops: a PD controller against Coulomb friction has a dead zone. At rest the D terms
vanish and static friction holds the P terms' wrench as long as it lies in the friction ellipsoid
of the hull model (the paper's eq. for the ellipsoid; the pressure centre shifts along F, so the
torque about the ECP is τ): F_x² + F_y² + (τ / e_r)² ≤ (μ m g)². The final error therefore obeys

    dead_zone_ratio = sqrt((kp |e_xy|)² + (kp_yaw e_yaw / e_r)²) / (μ m g) ≤ 1,

i.e. |e_xy| ≤ μ m g / kp and |e_yaw| ≤ μ m g e_r / kp_yaw (0.6 mm and 0.16° at ω = 60 rad/s).
tests/python/test_tbar_closed_loop.py checks that bound, that the T came to rest, and that its
contact with the table never separated.

Exit codes as the CLI's: 0 ok, 1 bad input, 3 solver failure, 5 model invalid.
"""

import argparse
import dataclasses
import math
import pathlib
import sys

import numpy as np

import ecpsim
from atomic_output import save_figure_atomically

ROOT = pathlib.Path(__file__).resolve().parents[1]
TBAR_SCENE = ROOT / "scenes" / "tbar.yaml"
TBAR_MESH = ROOT / "scenes" / "meshes" / "tbar.obj"
MODES = ("separated", "sliding", "sticking")  # Simulation.contacts()'s modes, bottom to top


@dataclasses.dataclass(frozen=True)
class Controller:
    """PD gains from a natural frequency and damping ratio, and the actuator's limits."""
    omega: float = 60.0       # rad/s: ω h = 0.6 at the scene's h = 0.01 s, a stable sampled loop
    zeta: float = 1.0         # critically damped
    force_max: float = 10.0   # N: above μ m g = 4.3 N; tipping at the CM's height needs > 100 N
    torque_max: float = 1.0   # N·m: above the torsional friction μ e_r m g = 0.43 N·m

    def __post_init__(self):
        # finite and positive; a damping ratio of zero is allowed
        for name in ("omega", "zeta", "force_max", "torque_max"):
            value, zero_ok = getattr(self, name), name == "zeta"
            if not math.isfinite(value) or value < 0 or (value == 0 and not zero_ok):
                raise ecpsim.InputError(f"controller {name} = {value}: expected a finite value "
                                        f"{'≥' if zero_ok else '>'} 0")


@dataclasses.dataclass
class ClosedLoopResult:
    """What one closed-loop run did, per step after t = 0."""
    time: np.ndarray            # (n,) s
    error: np.ndarray           # (n, 3) goal − pose: x, y (m) and yaw (rad, wrapped to ±π)
    modes: list                 # (n,) the T–table contact's mode after each step
    converged: np.ndarray       # (n,) bool: each step's report
    final_speed: float          # m/s, |v| of the CM at the end
    final_spin: float           # rad/s, |ω| at the end
    position_dead_zone: float   # m, μ m g / kp
    yaw_dead_zone: float        # rad, μ m g e_r / kp_yaw
    gains: dict                 # kp (N/m), kd (N·s/m), kp_yaw (N·m/rad), kd_yaw (N·m·s/rad)

    @property
    def final_error(self):
        """(3,) the last error: x, y (m), yaw (rad)."""
        return self.error[-1]

    @property
    def dead_zone_ratio(self):
        """The final error against the dead zone (module docstring): ≤ 1 when the T stopped
        where static friction holds the controller's wrench."""
        final = self.final_error
        return math.hypot(np.linalg.norm(final[:2]) / self.position_dead_zone,
                          final[2] / self.yaw_dead_zone)


def tbar_scene(duration):
    """The T-bar of scenes/tbar.yaml (mass, start pose, friction) on the table without its loads:
    the controller is the only actuator."""
    original = ecpsim.load_scene(str(TBAR_SCENE))
    tbar = original.bodies[0]
    return ecpsim.make_scene({
        "gravity": original.gravity, "h": 0.01, "duration": duration,
        "ground": {"friction": tbar["friction"]},
        "bodies": [{"name": "tbar", "mesh": str(TBAR_MESH), "mass": tbar["mass"],
                    "position": tbar["position"], "quaternion": tbar["quaternion"]}]})


def yaw_of(quaternion):
    """rad: the heading of the body's x axis in the table's plane, for (w, x, y, z)."""
    w, x, y, z = quaternion
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def wrapped(angle):
    """angle in [−π, π)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def saturated(vector, limit):
    """vector scaled down to length `limit` if longer (its direction kept)."""
    norm = float(np.linalg.norm(vector))
    return vector * (limit / norm) if norm > limit else vector


def run_closed_loop(goal, duration=3.0, controller=Controller()):
    """Drives the T-bar to goal = (x m, y m, yaw rad) for `duration` s; returns ClosedLoopResult.
    Raises ecpsim.SolverFailure if a step fails."""
    scene = tbar_scene(duration)
    sim = ecpsim.Simulation(scene)
    body = scene.bodies[0]
    m, inertia_zz = body["mass"], body["inertia"][2, 2]
    w, z = controller.omega, controller.zeta
    gains = {"kp": m * w * w, "kd": 2 * z * m * w,
             "kp_yaw": inertia_zz * w * w, "kd_yaw": 2 * z * inertia_zz * w}
    goal_xy, goal_yaw = np.asarray(goal[:2], float), float(goal[2])

    def pose_error():
        return np.append(goal_xy - sim.positions[0, :2],
                         wrapped(goal_yaw - yaw_of(sim.quaternions[0])))

    steps = int(round(duration / scene.h))  # ≥ 1: make_scene demands h ≤ duration
    time, error, modes, converged = np.empty(steps), np.empty((steps, 3)), [], np.empty(steps, bool)
    for k in range(steps):
        e, v, spin = pose_error(), sim.velocities[0], sim.angular_velocities[0, 2]
        force = saturated(gains["kp"] * e[:2] - gains["kd"] * v[:2], controller.force_max)
        torque = np.clip(gains["kp_yaw"] * e[2] - gains["kd_yaw"] * spin,
                         -controller.torque_max, controller.torque_max)
        sim.apply_wrench("tbar", force=[force[0], force[1], 0.0], torque=[0.0, 0.0, torque])
        sim.step()
        time[k], error[k] = sim.time, pose_error()
        modes.append(sim.contacts()[0]["mode"])
        converged[k] = sim.last_report["converged"]

    friction = sim.contacts()[0]["friction"]
    holding = friction["mu"] * m * np.linalg.norm(scene.gravity)  # N, μ m g
    return ClosedLoopResult(time, error, modes, converged,
                            float(np.linalg.norm(sim.velocities[0])),
                            float(np.linalg.norm(sim.angular_velocities[0])),
                            holding / gains["kp"], holding * friction["e_r"] / gains["kp_yaw"],
                            gains)


def plot(result, path):
    """The pose error (position in mm, yaw in degrees, log scale) and the contact mode over
    time, as one PNG at `path` (written atomically)."""
    from matplotlib.figure import Figure  # no pyplot: no GUI backend, safe in any thread

    figure = Figure(figsize=(7, 6.5), layout="constrained")
    position, yaw, mode = figure.subplots(3, 1, sharex=True,
                                          gridspec_kw={"height_ratios": [2, 2, 1]})
    # a floor for the log scale: errors of exactly zero happen only at t = 0 of a trivial goal
    floor = 1e-9
    position.semilogy(result.time, np.maximum(np.linalg.norm(result.error[:, :2], axis=1) * 1e3,
                                              floor))
    position.axhline(result.position_dead_zone * 1e3, color="grey", ls="--", lw=1,
                     label="dead zone μ m g / kp")
    position.set_ylabel("|e_xy| (mm)")
    position.legend(loc="upper right")
    yaw.semilogy(result.time, np.maximum(np.degrees(np.abs(result.error[:, 2])), floor))
    yaw.axhline(math.degrees(result.yaw_dead_zone), color="grey", ls="--", lw=1,
                label="dead zone μ m g e_r / kp_yaw")
    yaw.set_ylabel("|e_yaw| (°)")
    yaw.legend(loc="upper right")
    mode.step(result.time, [MODES.index(m) for m in result.modes], where="post")
    mode.set_yticks(range(len(MODES)), MODES)
    mode.set_ylim(-0.5, len(MODES) - 0.5)
    mode.set_ylabel("T–table contact")
    mode.set_xlabel("t (s)")
    figure.suptitle("T-bar to its goal pose: PD through apply_wrench")
    return save_figure_atomically(figure, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("-o", "--output", default="out/tbar_closed_loop", help="output folder")
    parser.add_argument("--goal", nargs=3, type=float, default=[0.25, 0.15, 150.0],
                        metavar=("X", "Y", "YAW_DEG"), help="goal: m, m, degrees (start: 0 0 90)")
    parser.add_argument("--duration", type=float, default=3.0, help="s")
    parser.add_argument("--omega", type=float, default=Controller.omega,
                        help="the loop's natural frequency, rad/s")
    args = parser.parse_args(argv)
    goal = (args.goal[0], args.goal[1], math.radians(args.goal[2]))
    try:
        result = run_closed_loop(goal, args.duration, Controller(omega=args.omega))
    except ecpsim.InputError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    except ecpsim.SolverFailure as error:
        print(f"solver failure: {error}", file=sys.stderr)
        return 3
    except ecpsim.ModelInvalid as error:
        print(f"model invalid: {error}", file=sys.stderr)
        return 5
    path = plot(result, pathlib.Path(args.output) / "tbar_closed_loop.png")
    ex, ey, eyaw = result.final_error
    print(f"final error after {result.time[-1]:.2f} s: x {ex * 1e3:+.4f} mm, y {ey * 1e3:+.4f} mm, "
          f"yaw {math.degrees(eyaw):+.4f}°; dead zone ratio {result.dead_zone_ratio:.6f} (≤ 1 at "
          f"rest); contact modes {sorted(set(result.modes))}; wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
