#!/usr/bin/env bash
# The full `ecpsim bench` sweep on this machine: N shards run side by side (one per core), then
# merged into OUT with its charts and results.md; the charts shown in README.md are copied into
# docs/figures/bench/. Usage: scripts/bench.sh [OUT] [extra ecpsim bench options…]
# (default out/bench; e.g. scripts/bench.sh out/quick --quick). Shards: ECPSIM_SHARDS (default nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/bench}"
shift || true
ecpsim="${ECPSIM:-./build/app/ecpsim}"
shards="${ECPSIM_SHARDS:-$(nproc)}"
mkdir -p "$out"

# each shard is one process with its own CSVs; a failed shard fails the script
seq 1 "$shards" | xargs -P "$shards" -I{} \
  "$ecpsim" bench --shard "{}/$shards" -o "$out/shard_{}" "$@"
"$ecpsim" bench --merge $(seq -f "$out/shard_%g" 1 "$shards") -o "$out"

mkdir -p docs/figures/bench
cp "$out"/work_precision_*.png "$out"/stability_*.png docs/figures/bench/
cp "$out/results.md" docs/bench_results.md
echo "results in $out/results.md, charts in docs/figures/bench/"
