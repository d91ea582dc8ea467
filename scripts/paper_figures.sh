#!/usr/bin/env bash
# Reproduces the paper's figures and its desk table from scratch and copies the figures shown in
# README.md into docs/figures/. Usage: scripts/paper_figures.sh [OUT]   (default out/paper)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/paper}"
ecpsim="${ECPSIM:-./build/app/ecpsim}"
mkdir -p "$out" docs/figures

ECPSIM="$ecpsim" bash scripts/desk_table.sh "$out/desk" | tee "$out/desk_table.md"
"$ecpsim" plot "$out/desk/hull"
for scene in tbar dumbbell; do
  "$ecpsim" run "scenes/$scene.yaml" -o "$out/$scene"
  "$ecpsim" plot "$out/$scene"
done
"$ecpsim" render scenes/tbar.yaml --time 0.2 -o "$out/tbar_frame.png" --width 960 --height 540
"$ecpsim" render scenes/dumbbell.yaml --time 0.3 -o "$out/dumbbell_frame.png" --width 960 \
  --height 540

cp "$out/desk/hull/desk_velocity.png" "$out/desk/hull/desk_patches.png" \
  "$out/tbar/tbar_ecp.png" "$out/tbar/tbar_vz_ax.png" "$out/tbar/tbar_patches.png" \
  "$out/dumbbell/dumbbell_cm.png" "$out/dumbbell/dumbbell_patches.png" \
  "$out/tbar_frame.png" "$out/dumbbell_frame.png" docs/figures/
echo "figures in docs/figures/, table in $out/desk_table.md"
