#!/usr/bin/env bash
# Renders the frames of the multi-body scenes shown in README.md ("Bodies touching bodies") into
# docs/figures/. Usage: scripts/scene_frames.sh   (ECPSIM=path/to/ecpsim to use another binary)
set -euo pipefail
cd "$(dirname "$0")/.."
ecpsim="${ECPSIM:-./build/app/ecpsim}"
mkdir -p docs/figures
# scene and the time of its frame: the stack at rest, the box under way, the T turned, the box
# dragged and turning in the gripper, the dominoes falling, the cube on the cup's floor, the peg
# pushed by the finger, the mug hanging from the hook, the cube on the mug's floor
for shot in stack:5 push_box:1.5 tbar_push:3 gripper:2 dominoes:0.6 cube_in_cup:1 peg_in_hole:0.02 hook:2.5 cube_in_mug:1; do
  scene="${shot%%:*}"
  "$ecpsim" render "scenes/$scene.yaml" --time "${shot##*:}" -o "docs/figures/${scene}_frame.png" \
    --width 960 --height 540
done
echo "frames in docs/figures/"
