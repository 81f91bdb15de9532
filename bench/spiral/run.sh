#!/usr/bin/env bash
# Spiral planner benchmark (bench/results/spiral.md):
#  1. the paper's 20 regions (bench/data/apostolidis2022, 1 UAV, ds 40 m, strict) with darp, boustrophedon and
#     spiral through bench/compare/run.sh (one evaluator, 1 m lattice);
#  2. a coastline-like bay (coastline.py: inlets, two islands, 3 UAVs 30/40/30 %, ds 20 m) through
#     `uavcover compare` with the three planners;
#  3. speed and memory: mesh, Lloyd (0/10/60/100 steps) and partition times from plan.json diagnostics, peak
#     RSS from /usr/bin/time, on squares of 1, 10 and 100 km2 at ds 20 m (about 1e4, 1e5, 1e6 triangles).
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
square() {  # side_m lloyd out.json
  python3 - "$1" "$2" "$3" <<'PY'
import json, math, sys
side, lloyd, out = float(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
lon0, lat0 = 24.40, 40.93
mx, my = 111320.0 * math.cos(math.radians(lat0)), 110540.0
h = side / 2
ring = [[lon0 + x / mx, lat0 + y / my] for x, y in [(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)]]
json.dump({"name": f"square {side:.0f} m", "area": {"type": "Polygon", "coordinates": [ring]}, "spacing_m": 20,
           "planner": "spiral", "planner_params": {"lloyd_iterations": lloyd},
           "uavs": [{"id": "a", "share": 0.3, "start": ring[0]}, {"id": "b", "share": 0.4, "start": ring[1]},
                    {"id": "c", "share": 0.3, "start": ring[2]}], "seed": 1}, open(out, "w"))
PY
}
mkdir -p "$work/speed"
runs=""
for spec in 1000:0 1000:10 1000:60 1000:100 3162:0 3162:10 10000:0; do
  side="${spec%%:*}"; lloyd="${spec##*:}"
  m="$work/speed/s${side}_l${lloyd}.json"
  square "$side" "$lloyd" "$m"
  echo "speed: side $side m, $lloyd Lloyd steps" >&2
  /usr/bin/time -f "%M %e" -o "$work/speed/s${side}_l${lloyd}.time" \
    "$bin" -q plan "$m" -o "$work/speed/s${side}_l${lloyd}" --no-images --no-evaluate
  runs="$runs $work/speed/s${side}_l${lloyd}"
done

python3 "$here/table.py" "$work" "$("$bin" --version)" $runs | tee "$out"
cp "$work/coastline/compare.png" "$repo/bench/results/spiral-coastline.png" 2>/dev/null || true
echo "wrote $out" >&2
