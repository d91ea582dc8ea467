#!/usr/bin/env bash
# The full `ecpsim bench` sweep on this machine: N shards run side by side (one per core), the
# scaling benchmark alone after them, then all merged into OUT with its charts and results.md;
# the charts shown in README.md are copied into docs/figures/bench/.
# Usage: scripts/bench.sh [OUT] [extra ecpsim bench options…] (default out/bench; e.g.
# scripts/bench.sh out/quick --quick). Shards: ECPSIM_SHARDS (default nproc).
# The drop sweep's mesh collections: ECPSIM_DROP_MESHES (default Debian's assimp test models and
# CGAL's demo meshes, unpacked into OUT/cgal-data).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/bench}"
shift || true
ecpsim="${ECPSIM:-./build/app/ecpsim}"
shards="${ECPSIM_SHARDS:-$(nproc)}"
mkdir -p "$out"

cgal_data=/usr/share/doc/libcgal-dev/data.tar.gz  # package libcgal-demo
drop_meshes="${ECPSIM_DROP_MESHES:-/usr/share/assimp/models}"
if [ -z "${ECPSIM_DROP_MESHES:-}" ] && [ -f "$cgal_data" ]; then
  mkdir -p "$out/cgal-data"
  tar xzf "$cgal_data" -C "$out/cgal-data" data/meshes
  drop_meshes="$drop_meshes $out/cgal-data/data/meshes"
fi

# each shard is one process with its own CSVs; a failed shard fails the script
# shellcheck disable=SC2086  # drop_meshes is a list of folders
seq 1 "$shards" | xargs -P "$shards" -I{} \
  "$ecpsim" bench --shard "{}/$shards" -o "$out/shard_{}" --no-scaling --drop-meshes $drop_meshes "$@"
# the scaling benchmark times steps against the number of bodies: alone, not beside the shards
"$ecpsim" bench --no-work-precision --no-stability --no-drops -o "$out/scaling" "$@"
parts=$(seq -f "$out/shard_%g" 1 "$shards")
if [ -f "$out/scaling/scaling.csv" ]; then parts="$parts $out/scaling"; fi
# shellcheck disable=SC2086  # parts is a list of folders
"$ecpsim" bench --merge $parts -o "$out"

mkdir -p docs/figures/bench
cp "$out"/work_precision_*.png "$out"/stability_*.png docs/figures/bench/
# the scaling chart, unless the run left the scaling benchmark out (--no-scaling)
if [ -f "$out/scaling.png" ]; then cp "$out/scaling.png" docs/figures/bench/; fi
cp "$out/results.md" docs/bench_results.md
echo "results in $out/results.md, charts in docs/figures/bench/"
