#!/usr/bin/env bash
# Quick-start command (1): installs dependencies, builds, and runs the main job.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/app/ecpsim hull scenes/meshes/tbar.obj --mass 2
