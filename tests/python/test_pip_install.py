"""`pip install` of the checkout into a venv (docs/python.md, "Build and import"): the module, its
stub and the mesh reader helper land side by side in the venv's site-packages, and the installed
module, imported with no PYTHONPATH from another folder, gives the build tree's numbers bit for bit,
reads meshes through the installed helper, and passes tests of tests/python/ run against it."""

import json
import os
import re
import subprocess
import sys

import numpy as np

import ecpsim
from conftest import SOURCE_DIR

BINARY_DIR = os.environ.get("ECPSIM_BINARY_DIR", str(SOURCE_DIR / "build"))
# s: for one command (the venv ≈ 3 s, pip on a built tree ≈ 2 s, a cold build minutes); a
# timeout names the stuck command instead of hanging ctest
COMMAND_TIMEOUT = 300
# tests/python/ files run against the installed module (≈ 5 s): each item of the module —
# stepping and state arrays, meshes read through the installed helper, run() against the CLI,
# frames and videos, scenes from files and dicts, sensors, rollouts, step Jacobians — and the
# docs' examples
INSTALLED_TESTS = ["test_simulation.py", "test_hull.py", "test_run.py", "test_render.py",
                   "test_docs.py", "test_scene.py", "test_make_scene.py", "test_sensors.py",
                   "test_rollout.py", "test_step_jacobians.py", "test_media.py"]

# run by the venv's python in an empty folder: what the installed module gives
PROBE = """\
import ctypes, json, sys
import ecpsim
slide = ecpsim.Simulation(ecpsim.load_scene(sys.argv[1]))
slide.step(10)
tbar = ecpsim.load_scene(sys.argv[2])
sim = ecpsim.Simulation(tbar)
sim.step(3)
getenv = ctypes.CDLL(None).getenv  # the module sets the helper's path with setenv(3)
getenv.restype = ctypes.c_char_p
print(json.dumps({
    "version": ecpsim.__version__, "file": ecpsim.__file__, "prefix": sys.prefix,
    "mesh_reader": (getenv(b"ECPSIM_MESH_READER") or b"").decode(),
    "slide": [slide.positions.tolist(), slide.velocities.tolist()],
    "tbar_inertia": tbar.bodies[0]["inertia"].tolist(),
    "tbar": [sim.positions.tolist(), sim.quaternions.tolist()],
}))
"""


def cmake_version():
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    return re.search(r"project\(\s*ecpsim\s+VERSION\s+([0-9.]+)", text).group(1)


def run(command, env, cwd):
    result = subprocess.run([str(c) for c in command], env=env, cwd=cwd, capture_output=True,
                            text=True, timeout=COMMAND_TIMEOUT)
    assert result.returncode == 0, f"{command}\n{result.stdout}\n{result.stderr}"
    return result.stdout


def test_pip_install_into_venv(tmp_path, scenes):
    # the environment of a user's shell: no PYTHONPATH to the build tree, no helper chosen
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "ECPSIM_MESH_READER")}
    env["ECPSIM_BUILD_DIR"] = BINARY_DIR
    env["PIP_NO_CACHE_DIR"] = "1"  # no copy of the wheel in ~/.cache/pip
    venv = tmp_path / "venv"
    work = tmp_path / "work"
    work.mkdir()

    # the commands of docs/python.md; Debian's numpy, setuptools and wheel through the system
    # site-packages, nothing downloaded (--no-index)
    run([sys.executable, "-m", "venv", "--system-site-packages", venv], env, work)
    run([venv / "bin" / "pip", "install", "--no-build-isolation", "--no-index", SOURCE_DIR],
        env, work)

    out = json.loads(run([venv / "bin" / "python", "-c", PROBE, scenes / "slide.yaml",
                          scenes / "tbar.yaml"], env, work))
    assert out["version"] == cmake_version() == ecpsim.__version__
    # the venv's copy, with its stub and the helper it runs beside it
    site = os.path.dirname(out["file"])
    assert os.path.realpath(out["prefix"]) == os.path.realpath(venv)
    assert out["file"].startswith(out["prefix"] + os.sep)
    assert out["mesh_reader"] == os.path.join(site, "ecpsim-mesh-reader")
    assert os.access(out["mesh_reader"], os.X_OK)
    with open(os.path.join(site, "ecpsim.pyi")) as stub:
        assert stub.read() == (SOURCE_DIR / "python" / "ecpsim.pyi").read_text()

    # the build tree's module (this process) gives the same doubles
    slide = ecpsim.Simulation(ecpsim.load_scene(str(scenes / "slide.yaml")))
    slide.step(10)
    np.testing.assert_array_equal(out["slide"][0], slide.positions)
    np.testing.assert_array_equal(out["slide"][1], slide.velocities)
    tbar = ecpsim.load_scene(str(scenes / "tbar.yaml"))
    sim = ecpsim.Simulation(tbar)
    sim.step(3)
    np.testing.assert_array_equal(out["tbar_inertia"], tbar.bodies[0]["inertia"])
    np.testing.assert_array_equal(out["tbar"][0], sim.positions)
    np.testing.assert_array_equal(out["tbar"][1], sim.quaternions)

    # tests of this folder against the installed module (their conftest finds the scenes
    # through ECPSIM_SOURCE_DIR)
    env["ECPSIM_SOURCE_DIR"] = str(SOURCE_DIR)
    tests = [SOURCE_DIR / "tests" / "python" / name for name in INSTALLED_TESTS]
    run([venv / "bin" / "python", "-m", "pytest", "-q", "-p", "no:cacheprovider", *tests], env,
        work)
