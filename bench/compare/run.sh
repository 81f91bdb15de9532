#!/usr/bin/env bash
# Planner comparison: plans the 20 regions of bench/data/apostolidis2022 (1 UAV, ds 40 m) in strict and
# coverage mode, and the thesis rectangle (bench/data/mondinelli2025/rectangle_3uav.json, 3 UAVs,
# ds 10 m), with every planner through `uavcover compare` (one evaluator: square footprint 1.5 ds swept
# along each leg, 1 m lattice), and writes bench/results/compare.md.
# usage: bench/compare/run.sh [BUILD_DIR]    env: PLANNERS=darp,boustrophedon MODES="strict coverage" ROIS="01 02"
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
data="$repo/bench/data"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-compare-bench}"
modes="${MODES:-strict coverage}"
rois="${ROIS:-$(seq -w 1 20 | tr '\n' ' ')}"
planners="${PLANNERS:-$("$bin" planners --json | python3 -c 'import json,sys; print(",".join(p["name"] for p in json.load(sys.stdin)))')}"
out="${OUT:-$repo/bench/results/compare.md}"
[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work"
for mode in $modes; do
  for n in $rois; do
    roi="roi$(printf %02d "$((10#$n))")"
    dir="$work/$mode/$roi"
    mkdir -p "$dir"
    python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); m["mode"]=sys.argv[2]; json.dump(m,open(sys.argv[3],"w"))' \
      "$data/apostolidis2022/$roi.json" "$mode" "$dir/mission.json"
    printf '%-9s %-5s\n' "$mode" "$roi" >&2
    "$bin" -q compare "$dir/mission.json" --planners "$planners" --lattice 1 --no-images --out "$dir" \
      2>"$dir/err" || echo "  failed: $(head -c 300 "$dir/err")" >&2
  done
done
mkdir -p "$work/rectangle"
"$bin" -q compare "$data/mondinelli2025/rectangle_3uav.json" --planners "$planners" --lattice 1 --out "$work/rectangle"
python3 "$here/table.py" "$data/apostolidis2022/paper_results.csv" "$work" "$modes" "$rois" "$planners" \
  "$("$bin" --version)" | tee "$out"
cp "$work/rectangle/compare.png" "$repo/bench/results/compare-rectangle.png" 2>/dev/null || true
echo "wrote $out" >&2
