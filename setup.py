"""`pip install --no-build-isolation .`: the ecpsim module built by the project's CMake.

The version is CMakeLists.txt's `project(ecpsim VERSION ...)`. build_ext reuses the CMake build
folder $ECPSIM_BUILD_DIR (default: build/, the folder of scripts/build.sh), configures it the way
scripts/build.sh does only when it holds no CMakeCache.txt, builds the module and the mesh reader
helper, and puts the module, its type stub and the helper side by side in the wheel: the module
runs the helper from its own folder. Reference: docs/python.md, "Build and import".
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = pathlib.Path(__file__).resolve().parent
SCRATCH_DIR = SOURCE_DIR / "build" / "setuptools"


def cmake_version():
    """`project(ecpsim VERSION x.y.z ...)` of CMakeLists.txt, where the version is written once."""
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*ecpsim\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if match is None:
        sys.exit(f"setup.py: {SOURCE_DIR / 'CMakeLists.txt'}: no `project(ecpsim VERSION x.y.z)`")
    return match.group(1)


def build_dir():
    """$ECPSIM_BUILD_DIR (relative to the checkout) or build/."""
    return (SOURCE_DIR / (os.environ.get("ECPSIM_BUILD_DIR") or "build")).resolve()


class CMakeBuild(build_ext):
    """Builds ecpsim_python and ecpsim-mesh-reader with CMake; copies what wheel_files.txt lists."""

    def run(self):
        # the wheel holds this build's files alone: setuptools keeps its build folder between
        # installs, and a file an earlier install left there would ship again (no Python modules
        # of ours are built into it)
        shutil.rmtree(self.build_lib, ignore_errors=True)
        super().run()

    def build_extension(self, ext):
        # a build in the checkout (pip install -e) would leave the module's files in its root;
        # PYTHONPATH=build/python is the development route
        if self.inplace or getattr(self, "editable_mode", False):
            sys.exit("setup.py: no editable install; use PYTHONPATH=build/python (docs/python.md)")
        build = build_dir()
        cache = build / "CMakeCache.txt"
        if not cache.exists():
            # build/ is configured as scripts/build.sh does it, so that the two reuse one build
            # (CMake picks Debian's python3); another folder for the Python running pip, the one
            # the venv was made from (it outlives the venv)
            options = ["-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"]
            if build != (SOURCE_DIR / "build").resolve():
                python = getattr(sys, "_base_executable", sys.executable)
                options.append(f"-DPython_EXECUTABLE={python}")
            self.run_cmake(["-S", SOURCE_DIR, "-B", build] + options)
        elif "ECPSIM_BUILD_PYTHON:BOOL=OFF" in cache.read_text():
            sys.exit(f"setup.py: {build} is configured with -DECPSIM_BUILD_PYTHON=OFF; "
                     "reconfigure it with ON, or set ECPSIM_BUILD_DIR to a new folder")
        # the build is left as it is configured: no option here would rebuild it
        self.run_cmake(["--build", build, "-j", str(os.cpu_count() or 1),
                        "--target", "ecpsim_python", "ecpsim-mesh-reader"])

        # the module, its stub and the helper, as CMake names them (python/CMakeLists.txt)
        listing = build / "python" / "wheel_files.txt"
        module, stub, reader = [pathlib.Path(line) for line in listing.read_text().splitlines()]
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        if not module.name.endswith(suffix):
            sys.exit(f"setup.py: {module} is built for another Python than {sys.executable} "
                     f"(expected the suffix {suffix}); set ECPSIM_BUILD_DIR to a new folder such "
                     "as build-pip, which is configured for the Python running pip")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, target)
        shutil.copy2(stub, target.with_name("ecpsim.pyi"))
        shutil.copy2(reader, target.with_name(reader.name))

    def run_cmake(self, arguments):
        command = ["cmake"] + [str(a) for a in arguments]
        print(" ".join(command), flush=True)
        subprocess.run(command, check=True)


SCRATCH_DIR.mkdir(parents=True, exist_ok=True)
setup(
    version=cmake_version(),
    ext_modules=[Extension("ecpsim", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # setuptools' own files (lib.*, bdist.*, ecpsim.egg-info) in a folder of their own under the
    # ignored build/, not among the CMake files nor in the checkout's root
    options={"build": {"build_base": str(SCRATCH_DIR)},
             "egg_info": {"egg_base": str(SCRATCH_DIR)}},
)
