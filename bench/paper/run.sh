#!/usr/bin/env bash
# Paper benchmark (Apostolidis et al. 2022, §3.1): plans the 20 regions of
# bench/data/apostolidis2022 in strict and coverage mode with the built CLI, evaluates each
# plan with `uavcover evaluate` (w = 1.5 ds, 1 m lattice), and prints a side-by-side table against
# the paper's published results (J1+J2+J3 = the paper's DARP planner, and the two ETHZ planners).
# Writes the Markdown table to bench/results/paper.md.
#
# usage: bench/paper/run.sh [BUILD_DIR]      (default: build; or set UAVCOVER=/path/to/uavcover)
# env:   DATA=bench/data/apostolidis2022  WORK=/tmp/uavcover-paper-bench  MODES="strict coverage"  ROIS="01 02 ..."
#        PARAMS='{"extend_legs": false}'  (planner_params merged into every mission, to measure a variant)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
data="${DATA:-$repo/bench/data/apostolidis2022}"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-paper-bench}"
modes="${MODES:-strict coverage}"
rois="${ROIS:-$(seq -w 1 20 | tr '\n' ' ')}"
params="${PARAMS:-{\}}"
out="${OUT:-$repo/bench/results/paper.md}"

[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin (build it, or pass BUILD_DIR / set UAVCOVER)" >&2; exit 2; }
[[ -f "$data/paper_results.csv" ]] || { echo "run.sh: benchmark data not found in $data" >&2; exit 2; }
mkdir -p "$work"

for mode in $modes; do
  for n in $rois; do
    roi="roi$(printf %02d "$((10#$n))")"
    dir="$work/$mode/$roi"
    rm -rf "$dir"
    mkdir -p "$dir"
    # the mission with the mode set
    python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); m["mode"]=sys.argv[2]; p=json.loads(sys.argv[4])
if p: m["planner_params"]={**m.get("planner_params",{}),**p}
json.dump(m,open(sys.argv[3],"w"),indent=1)' \
      "$data/$roi.json" "$mode" "$dir/mission.json" "$params"
    printf '%-9s %-5s ' "$mode" "$roi" >&2
    if "$bin" -q plan "$dir/mission.json" --out "$dir" 2>"$dir/plan.err"; then
      if "$bin" -q evaluate "$dir/mission.json" "$dir/paths.geojson" --out "$dir" --lattice 1 --no-images \
          2>"$dir/evaluate.err"; then
        echo "ok" >&2
      else
        echo "evaluate failed: $(head -c 200 "$dir/evaluate.err")" >&2
      fi
    else
      echo "plan failed: $(head -c 200 "$dir/plan.err")" >&2
    fi
  done
done

mkdir -p "$(dirname "$out")"
python3 "$here/table.py" "$data/paper_results.csv" "$work" "$modes" "$rois" "$("$bin" --version 2>/dev/null || echo uavcover)" \
  | tee "$out"
echo "wrote $out" >&2
