#!/usr/bin/env bash
# Re-blesses tests/engine/trajectory_hashes.txt, the table of the TrajectoryHash test, from the
# current build: run it only for a change that is meant to move trajectories, and say why in the
# commit message.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
table=tests/engine/trajectory_hashes.txt
build/tests/ecpsim_trajectory_hashes scenes > "$table.tmp"
mv "$table.tmp" "$table"
echo "wrote $table ($(grep -vc '^#' "$table") lines)"
