#!/usr/bin/env bash
# MILP planner on the paper's 20 regions (bench/data/apostolidis2022, 1 UAV, ds 40 m): milp against darp
# and boustrophedon through bench/compare/run.sh (`uavcover compare`, one evaluator, 1 m lattice), in
# strict and coverage mode. Writes bench/results/milp-compare.md; bench/results/milp.md quotes it.
# The paper-size and large-instance speed numbers are bench_milp's (bench/milp/bench_milp.cpp).
# usage: bench/milp/run.sh [BUILD_DIR]    env: MODES="strict coverage" ROIS="01 02"
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-milp-bench}"
out="${OUT:-$repo/bench/results/milp-compare.md}"
# bench/compare/run.sh also refreshes bench/results/compare-rectangle.png, which is compare.md's: kept as it was
png="$repo/bench/results/compare-rectangle.png"
mkdir -p "$work"
cp "$png" "$work/compare-rectangle.png.keep" 2>/dev/null || true
PLANNERS=darp,boustrophedon,milp WORK="$work/compare" OUT="$work/compare.md" \
  bash "$repo/bench/compare/run.sh" "$build" >/dev/null
cp "$work/compare-rectangle.png.keep" "$png" 2>/dev/null || true
{
  echo "# milp against darp and boustrophedon on the 20 regions"
  echo
  echo "Command: \`bench/milp/run.sh ${1:-build}\` (Release build); load average at the end (1/5/15 min):"
  echo "$(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores, so compute times are wall clock on a shared machine."
  sed -n '2,$p' "$work/compare.md"
} > "$out"
echo "wrote $out" >&2
