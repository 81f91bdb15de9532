#!/usr/bin/env bash
# Issue 27's CLI measure: `uavcover plan` with every export on the 5 km x 4 km field at spacing 10 m with
# 8 UAVs (bench/exports/field-5x4km.json), under /usr/bin/time -v: wall, user+system CPU, peak RSS, bytes
# written, and the trajectory file per UAV. With BEFORE=path/to/older/uavcover the same for that binary,
# and a byte check that the sampled trajectory at 0.1 s (--trajectory-step 0.1) equals the older default.
# Prints Markdown to stdout.
# usage: bench/exports/run.sh [BUILD_DIR]     env: BEFORE=...  WORK=/tmp/uavcover-bench-exports
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-bench-exports}"
mission="$here/field-5x4km.json"
formats=geojson,qgc,wpl,kml,dji,litchi,csv,trajectory
[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work"

row() {  # label binary outdir [extra args...]
  local label=$1 b=$2 out=$3
  shift 3
  /usr/bin/time -v "$b" -q plan "$mission" -o "$out" --export "$formats" "$@" >"$work/$label.log" 2>&1 ||
    { echo "run.sh: $label failed" >&2; tail -5 "$work/$label.log" >&2; exit 1; }
  local wall user sys rss bytes traj
  wall=$(grep "Elapsed (wall" "$work/$label.log" | awk '{print $NF}')
  user=$(grep "User time" "$work/$label.log" | awk '{print $NF}')
  sys=$(grep "System time" "$work/$label.log" | awk '{print $NF}')
  rss=$(grep "Maximum resident" "$work/$label.log" | awk '{printf "%.0f", $NF / 1024}')
  bytes=$(du -sb "$out" | awk '{printf "%.1f", $1 / 1e6}')
  traj=$(find "$out/trajectory" -name '*.csv' -printf '%s\n' | sort -n | tail -1 | awk '{printf "%.2f", $1 / 1e6}')
  echo "| $label | $wall | $user + $sys | $rss | $bytes | $traj |"
}

echo "\`bench/exports/run.sh\`: \`uavcover plan field-5x4km.json --export $formats\`, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
echo
echo "| binary | wall (m:ss) | user + sys s | peak RSS MB | written MB | largest trajectory file MB |"
echo "|---|---:|---:|---:|---:|---:|"
if [[ -n "${BEFORE:-}" ]]; then
  row before "$BEFORE" "$work/before"
fi
row after "$bin" "$work/after"
row "after, --trajectory-step 0.1" "$bin" "$work/sampled" --trajectory-step 0.1
if [[ -n "${BEFORE:-}" ]]; then
  same=yes
  for f in "$work/before/trajectory/"*.csv; do
    cmp -s "$f" "$work/sampled/trajectory/$(basename "$f")" || same=no
  done
  echo
  echo "Sampled at 0.1 s (\`--trajectory-step 0.1\`) byte-identical to the older default: $same."
  # every other export is unchanged by the segment form
  diff -rq "$work/before/export" "$work/after/export" >/dev/null && echo "Every other export byte-identical: yes." ||
    echo "Every other export byte-identical: NO."
fi
