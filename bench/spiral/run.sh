#!/usr/bin/env bash
# Spiral planner benchmark (bench/results/spiral.md):
#  1. the paper's 20 regions (bench/data/apostolidis2022, 1 UAV, ds 40 m, strict) with darp, boustrophedon and
#     spiral through bench/compare/run.sh (one evaluator, 1 m lattice);
#  2. a coastline-like bay (coastline.py: inlets, two islands, 3 UAVs 30/40/30 %, ds 20 m) through
#     `uavcover compare` with the three planners;
#  3. speed and memory: mesh, Lloyd (0/10/60/100 steps, local and CGAL) and partition times from plan.json
#     diagnostics, the stop latency inside Lloyd (--time-limit), peak RSS from /usr/bin/time, on squares of
#     1, 10 and 100 km2 at ds 20 m (about 1e4, 1e5, 1e6 triangles);
#  4. spiral variants on the 20 regions: size_by footprint, the smoothing pass at 45 and 90 degrees;
#  5. turn angles at the coverage waypoints (bench/spiral/angles.py) for darp, boustrophedon and the spirals.
# Env: SPEED_RUNS / STOP_RUNS override the speed specs (side:steps:method, side:method:limit).
# usage: bench/spiral/run.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-spiral-bench}"
out="${OUT:-$repo/bench/results/spiral.md}"
[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work"

# 1. the 20 regions
PLANNERS=darp,boustrophedon,spiral MODES=strict WORK="$work/rois" OUT="$work/rois.md" \
  bash "$repo/bench/compare/run.sh" "$build" >/dev/null

# 2. the coastline
python3 "$here/coastline.py" "$work/coastline.json" spiral 20
"$bin" -q compare "$work/coastline.json" --planners darp,boustrophedon,spiral --lattice 1 --out "$work/coastline"
"$bin" -q plan "$work/coastline.json" -o "$work/coastline-spiral" --no-images --no-evaluate

# 3. speed: squares of side 1, 3.16 and 10 km at ds 20 m
square() {  # side_m lloyd method out.json (bench/spiral/square.py)
  python3 "$here/square.py" "$1" "$2" "$3" "$4"
}
mkdir -p "$work/speed"
runs=""
# side:steps:method; CGAL's lloyd_optimize_mesh_2 only where it ends in minutes (10 km2: 320 s before)
for spec in ${SPEED_RUNS:-1000:0:local 1000:10:local 1000:60:local 1000:100:local 1000:10:cgal 1000:100:cgal \
    3162:0:local 3162:10:local 3162:100:local 10000:0:local 10000:10:local}; do
  IFS=: read -r side lloyd method <<<"$spec"
  name="s${side}_l${lloyd}_${method}"
  m="$work/speed/$name.json"
  square "$side" "$lloyd" "$method" "$m"
  echo "speed: side $side m, $lloyd Lloyd steps ($method)" >&2
  /usr/bin/time -f "%M %e" -o "$work/speed/$name.time" \
    "$bin" -q plan "$m" -o "$work/speed/$name" --no-images --no-evaluate
  runs="$runs $work/speed/$name"
done
# stop latency: a time limit that lands inside the Lloyd steps (10 km2, 100 steps)
for spec in ${STOP_RUNS:-3162:local:20}; do
  IFS=: read -r side method limit <<<"$spec"
  square "$side" 100 "$method" "$work/speed/stop.json"
  start=$(date +%s.%N)
  "$bin" -q plan "$work/speed/stop.json" -o "$work/speed/stop" --no-images --no-evaluate --time-limit "$limit" \
    2>/dev/null || true
  echo "$side $method $limit $(echo "$(date +%s.%N) - $start" | bc)" >>"$work/speed/stop.txt"
done

# 4. spiral variants on the same regions (spiral only, `uavcover compare`, 1 m lattice): triangles sized by
#    the swept footprint (size_by footprint) and the smoothing pass (smooth_reversal_deg 45 and 90)
for variant in size_by=footprint smooth_reversal_deg=45 smooth_reversal_deg=90; do
  for m in "$work"/rois/strict/roi*/mission.json; do
    roi="$(basename "$(dirname "$m")")"
    d="$work/variants/$variant/$roi"
    mkdir -p "$d"
    python3 - "$m" "$variant" "$d/mission.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
key, value = sys.argv[2].split("=")
m["planner"] = "spiral"
m["planner_params"] = {key: value if key == "size_by" else float(value)}
json.dump(m, open(sys.argv[3], "w"))
PY
    "$bin" -q compare "$d/mission.json" --planners spiral --lattice 1 --no-images --out "$d" >/dev/null
    "$bin" -q plan "$d/mission.json" -o "$d/plan" --no-images --no-evaluate
  done
done

# 5. turn angles at the coverage waypoints (18 regions, all but 6 and 18): darp, boustrophedon, spiral
#    and its variants, from each plan's paths.geojson
labels=""
for spec in darp: boustrophedon: spiral: spiral:size_by=footprint spiral:smooth_reversal_deg=45; do
  planner="${spec%%:*}"; variant="${spec#*:}"
  dirs=""
  for m in "$work"/rois/strict/roi*/mission.json; do
    roi="$(basename "$(dirname "$m")")"
    [[ "$roi" == roi06 || "$roi" == roi18 ]] && continue
    d="$work/angles/$planner${variant:+-$variant}/$roi"
    mkdir -p "$d"
    python3 - "$m" "$planner" "$variant" "$d/mission.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
m["planner"] = sys.argv[2]
m["planner_params"] = {}
if sys.argv[3]:
    key, value = sys.argv[3].split("=")
    m["planner_params"] = {key: value if key == "size_by" else float(value)}
json.dump(m, open(sys.argv[4], "w"))
PY
    "$bin" -q plan "$d/mission.json" -o "$d" --no-images --no-evaluate
    dirs="$dirs${dirs:+,}$d"
  done
  labels="$labels $planner${variant:+($variant)}@$dirs"
done
# shellcheck disable=SC2086 # one LABEL@DIRS argument per configuration, no spaces
python3 "$here/angles.py" $labels >"$work/angles.md"

python3 "$here/table.py" "$work" "$("$bin" --version)" $runs | tee "$out"
cp "$work/coastline/compare.png" "$repo/bench/results/spiral-coastline.png" 2>/dev/null || true
echo "wrote $out" >&2
