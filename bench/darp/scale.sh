#!/usr/bin/env bash
# DARP at scale (issue 16): the scale table. For each row (mega-cells N x UAVs U) `bench_plan mission N U`
# writes the synthetic square (ds 10 m, two no-fly zones, seeded random starts, equal shares) and a copy
# with shares 1..U; each is planned with `/usr/bin/time -v uavcover -q plan --no-images --no-evaluate`
# and the table gives wall and user time, peak RSS, convergence and the worst UAV's relative distance
# from its own share, beside the issue's "before" numbers and goals. Prints Markdown to stdout.
# usage: bench/darp/scale.sh [BUILD_DIR]   (needs uavcover and bench/bench_plan: -DUAVCOVER_BENCH=ON)
# env:   ROWS="100000:20 100000:50 300000:20 300000:50 1000000:20 1000000:50"  SHARES="equal unequal"
#        WORK=/tmp/uavcover-darp-scale  UAVCOVER=...  BENCH_PLAN=...
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
gen="${BENCH_PLAN:-$build/bench/bench_plan}"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-darp-scale}"
rows="${ROWS:-100000:20 100000:50 300000:20 300000:50 1000000:20 1000000:50}"
shares="${SHARES:-equal unequal}"
[[ -x "$bin" ]] || { echo "scale.sh: no uavcover binary at $bin" >&2; exit 2; }
[[ -x "$gen" ]] || { echo "scale.sh: no bench_plan at $gen (configure with -DUAVCOVER_BENCH=ON)" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work"

echo "DARP at scale: \`bench/darp/scale.sh\`, $("$bin" --version), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
echo
echo "| mega-cells | UAVs | shares | wall s | user s | peak RSS MB | converged | worst share dev % | issue's before | goal |"
echo "|---:|---:|---|---:|---:|---:|---|---:|---|---|"
for row in $rows; do
  IFS=: read -r n u <<<"$row"
  "$gen" mission "$n" "$u" >"$work/m_${n}_${u}_equal.json"
  python3 - "$work/m_${n}_${u}_equal.json" "$work/m_${n}_${u}_unequal.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
for i, u in enumerate(m["uavs"]):
    u["share"] = i + 1  # shares 1..U (normalised by the mission reader)
json.dump(m, open(sys.argv[2], "w"))
PY
  for s in $shares; do
    name="${n}_${u}_$s"
    /usr/bin/time -v "$bin" -q plan "$work/m_$name.json" -o "$work/p_$name" --no-images --no-evaluate \
      --max-cells 20000000 2>"$work/t_$name.txt" >/dev/null || { echo "| $n | $u | $s | failed |"; continue; }
    python3 - "$work/m_$name.json" "$work/p_$name/plan.json" "$work/t_$name.txt" "$n" "$u" "$s" <<'PY'
import json, re, sys
m, p, t = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), open(sys.argv[3]).read()
n, u, s = int(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
def grab(pat):
    return re.search(pat, t).group(1)
w = grab(r"Elapsed \(wall clock\) time.*: (\S+)").split(":")
wall = sum(float(x) * 60 ** k for k, x in enumerate(reversed(w)))
user = float(grab(r"User time \(seconds\): (\S+)"))
rss = int(grab(r"Maximum resident set size \(kbytes\): (\d+)")) / 1024
cells = [x["diagnostics"]["cells"] for x in p["uavs"]]
req = [x["share"] for x in m["uavs"]]
dev = max(abs(c / sum(cells) - r / sum(req)) / (r / sum(req)) for c, r in zip(cells, req))
# the issue's measurements before the work (equal shares) and its goals
before = {(100000, 20): "12.9 s, 240 MB", (100000, 50): "13.6 s", (300000, 20): "31 s, 525 MB",
          (300000, 50): "38 s", (1000000, 20): "121 s, 1.67 GB", (1000000, 50): "184 s"}
goal = {100000: "≤ 3 s", 300000: "≤ 15 s", 1000000: "≤ 60 s, ≤ 2 GB"}
conv = p["planner_diagnostics"].get("converged")
print(f"| {n} | {u} | {s} | {wall:.2f} | {user:.2f} | {rss:.0f} | {'yes' if conv else 'no'} | {100 * dev:.2f} | "
      f"{before.get((n, u), '') if s == 'equal' else ''} | {goal[n] + ', ' if n in goal else ''}every UAV within 2 % |")
PY
  done
done
