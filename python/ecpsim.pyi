"""Type stub of the ecpsim extension module (python/ecpsim_module.cpp); reference: docs/python.md.

Units are SI, vectors in the world frame, quaternions (w, x, y, z) body → world.
"""

import os
from types import TracebackType
from typing import (Any, Dict, Iterator, List, Literal, Mapping, Optional, Sequence, Type, Union,
                    overload)

import numpy as np
import numpy.typing as npt

Vector3 = Union[Sequence[float], npt.NDArray[np.float64]]
BodyRef = Union[str, int]
PathLike = Union[str, "os.PathLike[str]"]
ImageRef = Union[PathLike, npt.NDArray[np.uint8]]

__version__: str
"""The version of CMakeLists.txt's project(ecpsim VERSION ...), e.g. "0.1.0"."""

class InputError(ValueError):
    """Bad input, with the CLI's message (file:line:col: key = value: expected ...); exit code 1."""

class SolverFailure(RuntimeError):
    """A step could not be solved: time, body, residual and what was tried; exit code 3."""

class ModelInvalid(RuntimeError):
    """The scene's contact model does not apply; exit code 5."""

class Scene:
    """An immutable, validated scene; made by load_scene()."""

    @property
    def source(self) -> str: ...
    @property
    def h(self) -> float:
        """Time step, s."""
    @property
    def duration(self) -> float:
        """Duration of run(), s."""
    @property
    def gravity(self) -> npt.NDArray[np.float64]:
        """(3,) m/s²."""
    @property
    def model(self) -> str:
        """hull, planar, multipatch or point."""
    @property
    def body_names(self) -> List[str]: ...
    @property
    def bodies(self) -> List[Dict[str, Any]]:
        """Per body: name, kinematic, mass, inertia (3, 3), position, quaternion, velocity,
        angular_velocity, friction, mesh_vertices."""
    @property
    def obstacles(self) -> List[Dict[str, Any]]:
        """Per obstacle: name, friction."""
    @property
    def grippers(self) -> List[Dict[str, Any]]:
        """Per gripper: name, jaws (two body names, the first closing along +axis), axis (frame
        coordinates), force (N, or the scene's expression of t)."""
    @property
    def contact_names(self) -> List[str]:
        """'body.other' per potential contact, the order of Simulation.contacts()."""
    @property
    def warnings(self) -> List[str]: ...

class State:
    """A saved state (Simulation.get_state()), restored bit for bit by Simulation.set_state();
    copyable and picklable (pickle.loads(pickle.dumps(s)) continues bit for bit)."""

    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def quaternions(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]: ...
    def __copy__(self) -> "State": ...
    def __deepcopy__(self, memo: dict) -> "State": ...
    def __getstate__(self) -> tuple:
        """pickle: ('ecpsim.State', version, record), the record the state's JSON text (the same
        state record as a checkpoint's, every double a hexadecimal float)."""
    def __setstate__(self, state: tuple) -> None: ...

class Simulation:
    """One simulation of a Scene, stepped from Python; step() and render() release the GIL."""

    def __init__(self, scene: Scene, *, threads: int = 1) -> None:
        """threads: how many threads solve a step's contact islands (the same result for any)."""
    @property
    def threads(self) -> int: ...
    @threads.setter
    def threads(self, threads: int) -> None: ...
    def step(self, n: int = 1) -> None:
        """n steps; last_report then holds the last one's {converged, iterations, residual, ...}.
        Ctrl-C stops the step in progress, undone, and raises KeyboardInterrupt."""
    def reset(self) -> None: ...
    @property
    def scene(self) -> Scene: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def body_names(self) -> List[str]: ...
    @property
    def last_report(self) -> Dict[str, Any]:
        """{converged, iterations, residual, retries, substeps, models, failure}: of a failed
        step, converged False and failure its message."""
    positions: npt.NDArray[np.float64]
    """(n, 3) centres of mass, m; settable for dynamic bodies."""
    quaternions: npt.NDArray[np.float64]
    """(n, 4) (w, x, y, z); settable (normalized)."""
    velocities: npt.NDArray[np.float64]
    """(n, 3) m/s."""
    angular_velocities: npt.NDArray[np.float64]
    """(n, 3) rad/s, world frame."""
    def get_state(self) -> State: ...
    def set_state(self, state: State) -> None:
        """Raises InputError for poses inside an obstacle or another body."""
    def apply_wrench(
        self,
        body: BodyRef,
        force: Vector3 = ...,
        torque: Vector3 = ...,
        at: Optional[Vector3] = None,
    ) -> None:
        """force (N) at world point `at` (default the CM) and torque (N·m) for the next step."""
    def set_kinematic_target(
        self, body: BodyRef, position: Vector3, quaternion: Optional[Sequence[float]] = None
    ) -> None:
        """A kinematic body's pose at the end of the next step."""
    def set_gripper_target(
        self,
        gripper: Union[str, int],
        position: Vector3,
        quaternion: Optional[Sequence[float]] = None,
        force: Optional[float] = None,
    ) -> None:
        """A gripper frame's pose at the end of the next step, and its closing force (N on each
        jaw, ≥ 0) from the next step on."""
    def set_mass(
        self, body: BodyRef, mass: float, inertia: Optional[npt.ArrayLike] = None
    ) -> None:
        """A dynamic body's mass (kg) from the next step on, in this Simulation only; the inertia
        scales with it unless given (3 principal moments or (3, 3), kg·m²). reset() restores
        the scene's. Raises InputError (the loader's message) and changes nothing for a bad
        value."""
    def set_inertia(self, body: BodyRef, inertia: npt.ArrayLike) -> None:
        """A dynamic body's inertia (kg·m², about the CM in body axes): 3 principal moments or a
        (3, 3) symmetric positive definite matrix; as set_mass."""
    def set_friction(
        self,
        contact: Union[str, int],
        mu: Optional[float] = None,
        e_t: Optional[float] = None,
        e_o: Optional[float] = None,
        e_r: Optional[Union[float, str]] = None,
    ) -> None:
        """A contact's friction (a Scene.contact_names name such as 'box.ground', or an index);
        None keeps a value; as set_mass."""
    class StepJacobians:
        """The derivatives of one step; unpacks as A, B. State coordinates per dynamic body (in
        the order of `bodies`): [p (m), θ (rad), v (m/s), ω (rad/s)], world frame, θ a turn
        applied in the world frame (q = exp(θ) ⊗ q₀); inputs per dynamic body: [force (N) at
        the CM, torque (N·m)] over the step."""

        @property
        def A(self) -> npt.NDArray[np.float64]:
            """(12 n, 12 n) ∂x⁺/∂x."""
        @property
        def B(self) -> npt.NDArray[np.float64]:
            """(12 n, 6 n) ∂x⁺/∂u."""
        @property
        def bodies(self) -> List[str]:
            """The dynamic bodies, in the blocks' order."""
        @property
        def flags(self) -> Dict[str, Any]:
            """degenerate (bool: a pair with both members ≈ 0; A, B one element of the
            generalized Jacobian), isolated (bool: False where H is singular; minimum-norm
            solution), method ('implicit_function' or 'implicit_function_minimum_norm'),
            residual, A_determined and B_determined (bool arrays of A's and B's shapes),
            islands (per island: bodies, unknowns, rank, degenerate_pairs, residual)."""
        def __iter__(self) -> Iterator[npt.NDArray[np.float64]]: ...
        def __len__(self) -> int: ...
        def __getitem__(self, i: int) -> npt.NDArray[np.float64]: ...
    def step_jacobians(self) -> "Simulation.StepJacobians":
        """The derivatives of the next step at the current state and pending wrenches (the
        simulation is not advanced): A, B = sim.step_jacobians(). Raises ModelInvalid for the
        multipatch and point models and for a step that needed sub-steps."""
    @overload
    def contacts(self, as_arrays: Literal[False] = ...) -> List[Dict[str, Any]]:
        """Per potential contact: name, body, other, other_is_body, a1, a2, normal, tangent,
        tangent2, p_n, p_t, p_o, p_r, sigma, f_n, f_t, f_o, f_r, force, mode, model, friction."""
    @overload
    def contacts(self, as_arrays: Literal[True]) -> Dict[str, Any]:
        """The same keys (but friction) as numpy arrays, a row per contact; lists of names,
        modes and models."""
    def sensor(self, body: BodyRef) -> npt.NDArray[np.float64]:
        """(6,) force (N) and moment (N·m) a kinematic body's sensor read over the last step."""
    def render(
        self,
        width: int = 640,
        height: int = 480,
        camera: Optional[Mapping[str, Any]] = None,
        overlays: bool = True,
    ) -> npt.NDArray[np.uint8]:
        """(height, width, 3) RGB, top row first."""
    def record(
        self,
        path: PathLike,
        fps: Optional[float] = None,
        duration: Optional[float] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        camera: Optional[Mapping[str, Any]] = None,
        overlays: bool = True,
    ) -> Dict[str, Any]:
        """Steps `duration` s (default scene.duration) and writes an MP4 as `ecpsim run --video`:
        {path, frames, steps, time}. fps, width, height default to the scene's output block."""
    def recorder(
        self,
        path: PathLike,
        fps: Optional[float] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        camera: Optional[Mapping[str, Any]] = None,
        overlays: bool = True,
    ) -> Recorder:
        """An MP4 fed by your loop: `with sim.recorder(p) as rec: sim.step(); rec.capture()`."""

class Recorder:
    """An MP4 being written from a Simulation (Simulation.recorder())."""

    def capture(self) -> None:
        """Renders the frames due at the Simulation's time (frame k at k / fps)."""
    def close(self) -> None:
        """Finishes the video and renames it to its path."""
    def __enter__(self) -> Recorder: ...
    def __exit__(
        self,
        exc_type: Optional[Type[BaseException]],
        exc_value: Optional[BaseException],
        traceback: Optional[TracebackType],
    ) -> Literal[False]: ...
    @property
    def frames(self) -> int: ...
    @property
    def path(self) -> str: ...
    @property
    def closed(self) -> bool: ...

def load_scene(
    path: Union[str, os.PathLike], overrides: Optional[Union[Mapping[str, Any], Sequence[str]]] = None
) -> Scene:
    """A YAML scene with the CLI's --set overrides, validated."""

def make_scene(
    tree: Mapping[str, Any],
    overrides: Optional[Union[Mapping[str, Any], Sequence[str]]] = None,
    base_dir: Union[str, os.PathLike] = ".",
) -> Scene:
    """A scene from a dict that is the YAML format's tree, read by the file's loader; mesh
    paths relative to base_dir."""

class SceneWarning(UserWarning):
    """A scene loaded with a note that is no error (a mesh of implausible size)."""

def run(
    scene: Scene, duration: Optional[float] = None, every: Optional[int] = None
) -> Dict[str, npt.NDArray[np.float64]]:
    """The trajectory as trajectory.csv's columns."""

def rollout(
    simulations: Sequence[Simulation],
    steps: int,
    threads: Optional[int] = None,
    controls: Optional[npt.ArrayLike] = None,
) -> Dict[str, npt.NDArray[Any]]:
    """Steps each Simulation `steps` times on C++ threads (None: the machine's) without the GIL;
    returns positions (n_sims, steps, n_bodies, 3), quaternions (..., 4), velocities,
    angular_velocities, time (n_sims, steps) and converged (n_sims, steps, bool), the same
    doubles whatever `threads` is. The simulations need as many bodies each. controls: None or
    (n_sims, steps, n_bodies, 6) force (N, world, at the CM) and torque (N·m) per step, as
    apply_wrench; zero on kinematic bodies. A failed step stops its simulation at its last good
    state; after the others finish the first failure is raised (SolverFailure, ModelInvalid or
    InputError) with attributes simulation, steps_done, failures and results (the completed
    simulations' arrays and their indices, results['simulations']). Ctrl-C stops every step in
    progress, undone (docs/python.md, "Ctrl-C")."""

def hull(
    mesh_path: Union[str, os.PathLike],
    scale: Optional[float] = None,
    units: Optional[str] = None,
    mass: Optional[float] = None,
    density: Optional[float] = None,
) -> Dict[str, Any]:
    """A, b (A y ≤ b, body frame), vertices, faces, volume, mass, inertia, ..."""

def compare_images(
    expected: ImageRef,
    actual: ImageRef,
    threshold: int = 24,
    max_fraction: float = 0.0005,
    diff: Optional[PathLike] = None,
) -> Dict[str, Any]:
    """As `ecpsim compare`: match, same_size, total_pixels, differing_pixels,
    differing_fraction, max_channel_difference, summary, diff_image, diff."""
