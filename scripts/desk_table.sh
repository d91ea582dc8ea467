#!/usr/bin/env bash
# The desk comparison (issue 5, the paper's table): runs scenes/desk.yaml with the hull, planar and
# multipatch contact models, copies the other models' trajectories next to the hull run's (so that
# `ecpsim plot DIR/hull` draws the differences) and prints a markdown table of max |Δv_x| and
# max |Δω_z| over the run vs the hull model and the median time per step of each model.
# Usage: scripts/desk_table.sh [DIR]   (default out/desk; ECPSIM=path/to/ecpsim to pick a binary)
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-out/desk}"
ecpsim="${ECPSIM:-./build/app/ecpsim}"
if [[ ! -x "$ecpsim" ]]; then
  echo "desk_table.sh: $ecpsim not found or not executable; build first (scripts/build.sh) or set ECPSIM" >&2
  exit 1
fi

# (the logs go beside DIR, whose parent a fresh checkout may not have)
mkdir -p "$(dirname "$dir")"
for model in hull planar multipatch; do
  "$ecpsim" run scenes/desk.yaml -o "$dir/$model" --model "$model" > "$dir.$model.log" 2>&1 || {
    echo "desk_table.sh: ecpsim run --model $model failed; see $dir.$model.log" >&2
    exit 1
  }
done
cp "$dir/planar/trajectory.csv" "$dir/hull/trajectory_planar.csv"
cp "$dir/multipatch/trajectory.csv" "$dir/hull/trajectory_multipatch.csv"

# max |x_model − x_hull| of columns vx and wz over rows with the same t (the same step grid)
max_differences() {
  awk -F, '
    FNR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    NR == FNR { vx[$1] = $col["vx"]; wz[$1] = $col["wz"]; next }
    !($1 in vx) { print "desk_table.sh: t = " $1 " missing in the hull run" > "/dev/stderr"; exit 1 }
    {
      dv = $col["vx"] - vx[$1]; if (dv < 0) dv = -dv; if (dv > max_dv) max_dv = dv
      dw = $col["wz"] - wz[$1]; if (dw < 0) dw = -dw; if (dw > max_dw) max_dw = dw
    }
    END { printf "%.2e | %.2e", max_dv, max_dw }
  ' "$dir/hull/trajectory.csv" "$1"
}

median_us() {
  sed -n 's/.*"median_step_us": *\([0-9.eE+-]*\).*/\1/p' "$dir/$1/summary.json"
}

hull_us="$(median_us hull)"
row() {  # model, label, trajectory, paper ms
  local us diffs
  us="$(median_us "$1")"
  diffs="$(max_differences "$3")"
  awk -v label="$2" -v d="$diffs" -v us="$us" -v hull="$hull_us" -v paper="$4" 'BEGIN {
    printf "| %s | %s | %.1f µs | %.2f | %s ms | %.2f |\n", label, d, us, us / hull, paper, paper / 5.3
  }'
}

echo "| model | max \|Δv_x\| vs hull (m/s) | max \|Δω_z\| vs hull (rad/s) | median time per step | ratio to hull | paper (MATLAB) | paper's ratio |"
echo "|---|---|---|---|---|---|---|"
row planar "planar sliding (WAFR 2018)" "$dir/planar/trajectory.csv" 2.2
row hull "hull ECP (this paper)" "$dir/hull/trajectory.csv" 5.3
row multipatch "multi-patch (IDETC 2018)" "$dir/multipatch/trajectory.csv" 48.7
