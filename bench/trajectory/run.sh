#!/usr/bin/env bash
# The two trajectory methods on one real-size plan (docs/trajectory.md, issue 33): plans MISSION (default
# bench/exports/field-5x4km.json, 5 km x 4 km, spacing 10 m, 8 UAVs) and prints bench_trajectory's table
# (Markdown) for it.
# usage: bench/trajectory/run.sh [BUILD_DIR] [MISSION] [ORDER]     env: WORK=/tmp/uavcover-bench-trajectory
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
mission="${2:-$repo/bench/exports/field-5x4km.json}"
order="${3:-5}"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-bench-trajectory}"
[[ -x "$build/uavcover" && -x "$build/bench/bench_trajectory" ]] ||
  { echo "run.sh: needs $build/uavcover and $build/bench/bench_trajectory (UAVCOVER_BENCH=ON)" >&2; exit 2; }
rm -rf "$work"
"$build/uavcover" -q plan "$mission" -o "$work" --no-evaluate --no-images
echo "\`bench/trajectory/run.sh\`: $(basename "$mission"), order $order, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)."
echo
"$build/bench/bench_trajectory" "$work" "$order"
