#!/usr/bin/env bash
# Speed against an earlier revision: builds the engine and island benchmarks of REV in a git
# worktree under build/against/, then runs them and this tree's alternately, ROUNDS times each
# (the machine is shared and noisy: alternation spreads its drift over both), and prints per
# benchmark the median CPU time of each and their ratio this/REV.
#   bash scripts/bench_against.sh REV [ROUNDS]   (ROUNDS: 5 by default)
set -euo pipefail
cd "$(dirname "$0")/.."
rev=${1:?usage: bash scripts/bench_against.sh REV [ROUNDS]}
rounds=${2:-5}
sha=$(git rev-parse --verify "$rev^{commit}")
base=build/against/$sha
if [ ! -d "$base" ]; then
  git worktree prune  # a worktree whose folder a clean build removed is registered still
  git worktree add --detach "$base" "$sha" >/dev/null
fi
cmake -S "$base" -B "$base/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DECPSIM_BUILD_TESTS=OFF \
  -DECPSIM_BUILD_PYTHON=OFF >/dev/null
cmake --build "$base/build" -j "$(nproc)" --target ecpsim_bench_engine ecpsim_bench_island
bash scripts/build.sh
out=$(mktemp -d)
for ((i = 1; i <= rounds; ++i)); do
  for bench in engine island; do
    "$base/build/bench/ecpsim_bench_$bench" --benchmark_format=json >"$out/base_${bench}_$i.json"
    "build/bench/ecpsim_bench_$bench" --benchmark_format=json >"$out/this_${bench}_$i.json"
  done
done
python3 - "$out" "$rev" <<'PY'
import collections, glob, json, statistics, sys
out, rev = sys.argv[1], sys.argv[2]
times, units = collections.defaultdict(list), {}
for path in glob.glob(f"{out}/*.json"):
    which = path.rsplit("/", 1)[1].split("_")[0]
    for b in json.load(open(path))["benchmarks"]:
        times[(b["name"], which)].append(b["cpu_time"])
        units[b["name"]] = b["time_unit"]
print(f"median CPU time per step of {len(times[next(iter(times))])} runs each")
print(f"{'benchmark':28s} {rev:>12s} {'this':>12s} {'this/' + rev:>14s}")
for name in sorted(units):
    if not times[(name, "base")] or not times[(name, "this")]:
        print(f"{name:28s} (in one revision only)")
        continue
    base, this = statistics.median(times[(name, "base")]), statistics.median(times[(name, "this")])
    unit = units[name]
    print(f"{name:28s} {base:9.3f} {unit} {this:9.3f} {unit} {this / base:14.3f}")
PY
rm -r "$out"
