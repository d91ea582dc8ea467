#!/usr/bin/env bash
# Installs every build, test and run dependency of ecpsim from Debian 12 packages.
# Idempotent: packages already present are left as they are; safe to run again.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  # KLU: the sparse LU of an island's Newton matrix (engine/solver/sparse_factorizations.h)
  libsuitesparse-dev
  libassimp-dev libosmesa6-dev libpng-dev zlib1g-dev libfreetype-dev fonts-dejavu-core
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  libccd-dev libyaml-cpp-dev libcli11-dev libmuparser-dev libfmt-dev nlohmann-json3-dev
  ffmpeg gnuplot-nox
  # tests: assimp's own test models (a mirrored-transform FBX, and every file through `ecpsim hull`);
  # Python generates the corrupt-mesh corpus (tests/fixtures/make_mesh_corpus.py)
  assimp-testmodels python3
  # the Python module (python/) and its tests (tests/python/), for Debian's python3
  pybind11-dev python3-dev python3-numpy python3-pytest
  # `pip install --no-build-isolation .` into a venv (pyproject.toml, setup.py: setuptools runs
  # CMake, whose pybind11 is pybind11-dev's; no pybind11 Python package needed)
  python3-venv python3-pip python3-setuptools python3-wheel
  # the examples (examples/): Dask sweeps on a LocalCluster or a cluster, matplotlib plots
  python3-distributed python3-matplotlib
  libmujoco-dev libbullet-dev libode-dev
  # libmujoco-dev's CMake config names /usr/include/libqhull_r/ without depending on its package
  libqhull-dev
  # public meshes for `ecpsim bench`'s drop sweep: assimp's test models, CGAL's demo data
  assimp-testmodels libcgal-demo
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
