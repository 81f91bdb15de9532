#!/usr/bin/env bash
# "planner": "auto" on the paper's 20 regions (bench/data/apostolidis2022, strict mode as given):
# the chosen planner and its figures per region, and the others' figures, into bench/results/auto.md.
# usage: bench/auto/run.sh [BUILD_DIR]   env: OBJECTIVE=time  LIMIT=20 (s per region)  ROIS="01 02 ..."
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
bin="${UAVCOVER:-${1:-$repo/build}/uavcover}"
data="$repo/bench/data/apostolidis2022"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-auto-bench}"
objective="${OBJECTIVE:-time}"
limit="${LIMIT:-20}"
rois="${ROIS:-$(seq -w 1 20 | tr '\n' ' ')}"
out="${OUT:-$repo/bench/results/auto.md}"
[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin" >&2; exit 2; }
mkdir -p "$work"
for n in $rois; do
  roi="roi$(printf %02d "$((10#$n))")"
  dir="$work/$roi"; rm -rf "$dir"; mkdir -p "$dir"
  python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); m["planner"]="auto"; m.pop("planner_params",None)
m["objective"]=sys.argv[3]; json.dump(m,open(sys.argv[2],"w"),indent=1)' "$data/$roi.json" "$dir/mission.json" "$objective"
  "$bin" -q plan "$dir/mission.json" --out "$dir" --time-limit "$limit" --no-images 2>"$dir/plan.err" || true
  echo "$roi done" >&2
done
python3 - "$work" "$out" "$objective" "$limit" "$rois" <<'PY'
import json, os, sys
work, out, objective, limit, rois = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5].split()
names, rows = [], []
for n in rois:
    roi = "roi%02d" % int(n)
    p = os.path.join(work, roi, "plan.json")
    if not os.path.exists(p):
        rows.append((roi, None, open(os.path.join(work, roi, "plan.err")).read().strip()[:120])); continue
    s = json.load(open(p))["selection"]
    for c in s["candidates"]:
        if c["planner"] not in names: names.append(c["planner"])
    rows.append((roi, s, ""))
def cell(c):
    if "figures" not in c: return c["status"]
    f = c["figures"]
    t = "%.1f min, %.2f %%, %d turns, %.0f m" % (f["time_min"], 100 * f["poc"], f["turns"], f["length_m"])
    return ("**%s**" % t) if c["status"] == "won" else t
with open(out, "w") as o:
    o.write("# `\"planner\": \"auto\"` on the paper's 20 regions\n\n")
    o.write("Made by `bench/auto/run.sh` (objective `%s`, `--time-limit %s` s per region, shared among the "
            "planners; strict mode; the missions of bench/data/apostolidis2022). Each cell: flight time "
            "(eq. 17), PoC, turns, length; the winner in bold. The rule: PoC at least the best less 0.5 points.\n\n" % (objective, limit))
    o.write("| region | chosen | " + " | ".join(names) + " |\n|---|---|" + "---|" * len(names) + "\n")
    wins = {}
    for roi, s, err in rows:
        if s is None:
            o.write("| %s | failed: %s |%s\n" % (roi, err, " |" * len(names))); continue
        wins[s["winner"]] = wins.get(s["winner"], 0) + 1
        by = {c["planner"]: c for c in s["candidates"]}
        o.write("| %s | %s | %s |\n" % (roi, s["winner"], " | ".join(cell(by[n]) if n in by else "-" for n in names)))
    o.write("\nWins: " + ", ".join("%s %d" % kv for kv in sorted(wins.items())) + "\n")
PY
echo "wrote $out" >&2
