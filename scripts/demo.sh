#!/usr/bin/env bash
# Quick-start command (1): installs dependencies, builds, and runs the main job: the paper's T-bar
# scene to a trajectory, PNG frames, an MP4 video and the paper's plots, in out/tbar/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/app/ecpsim run scenes/tbar.yaml -o out/tbar --frames --video
./build/app/ecpsim plot out/tbar
echo "main job done: out/tbar/{trajectory.csv,summary.json,frames/,video.mp4,*.png}"
