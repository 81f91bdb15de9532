#!/usr/bin/env bash
# SMT planner benchmark (issue 15): the thesis rectangle of Table 5.3 (bench/data/mondinelli2025) with
# POPCORN's 5-minute flight-time limit, and the 20 regions of bench/data/apostolidis2022 (1 UAV, ds 40 m,
# coverage mode) under a 25-minute limit (the whole battery: the missions' battery_reserve is set to 0,
# so that the engine's battery sorties, endurance x (1 - battery_reserve), hold the 25-minute routes),
# each with `uavcover compare --planners smt,darp` (one evaluator) plus `uavcover plan` for the smt
# plan's route diagnostics. Writes bench/results/smt.md.
# usage: bench/smt/run.sh [BUILD_DIR]    env: ROIS="01 02" MODE=coverage ROI_PARAMS='{"max_flight_time_s":1500}' RECT=1
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
data="$repo/bench/data"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-smt-bench}"
rois="${ROIS:-$(seq -w 1 20 | tr '\n' ' ')}"
mode="${MODE:-coverage}"
out="${OUT:-$repo/bench/results/smt.md}"
# smt parameters on the 20 regions (JSON)
export ROI_PARAMS="${ROI_PARAMS:-}"
[[ -n "$ROI_PARAMS" ]] || ROI_PARAMS='{"max_flight_time_s":1500}'
[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work"

# mission variants: name, source, python edit of the mission dict m
variant() {  # name source edit
  mkdir -p "$work/$1"
  python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); exec(sys.argv[2]); json.dump(m,open(sys.argv[3],"w"))' \
    "$2" "$3" "$work/$1/mission.json"
}
run() {  # name: compare smt,darp and plan smt alone (for its route diagnostics)
  local dir="$work/$1"
  printf '%s\n' "$1" >&2
  "$bin" -q compare "$dir/mission.json" --planners smt,darp --lattice 1 --no-images --out "$dir/compare" \
    2>"$dir/err" || echo "  compare failed: $(head -c 300 "$dir/err")" >&2
  "$bin" -q plan "$dir/mission.json" --no-evaluate --no-images --out "$dir/plan" \
    2>>"$dir/err" || echo "  plan failed: $(head -c 300 "$dir/err")" >&2
}
rect="$data/mondinelli2025/rectangle_3uav.json"
# the thesis's POPCORN run: 3 UAVs, 3 m/s, 5-minute limit (its 3 routes); DARP gets the same UAVs
variant rect3 "$rect" 'm["planner"]="smt"; m["planner_params"]={"max_flight_time_s":300}'
# one home point at the south-west corner, routes as sorties of one UAV
variant rect1 "$rect" 'm["planner"]="smt"; m["uavs"]=[dict(m["uavs"][0], start=m["area"]["coordinates"][0][0])]; m["planner_params"]={"max_flight_time_s":300}'
variant rect1_diag "$rect" 'm["planner"]="smt"; m["uavs"]=[dict(m["uavs"][0], start=m["area"]["coordinates"][0][0])]; m["planner_params"]={"max_flight_time_s":300,"diagonal_edges":True}'
variant rect1_pen "$rect" 'm["planner"]="smt"; m["uavs"]=[dict(m["uavs"][0], start=m["area"]["coordinates"][0][0])]; m["planner_params"]={"max_flight_time_s":300,"turn_penalty_m":10}'
# home at the field's centre (the thesis's take-off point is not given): square tiles, strips, strips + penalty
centre='c=m["area"]["coordinates"][0]; m["uavs"]=[dict(m["uavs"][0], start=[(c[0][0]+c[2][0])/2,(c[0][1]+c[2][1])/2])]; m["planner"]="smt"; '
variant rect1c "$rect" "$centre"'m["planner_params"]={"max_flight_time_s":300}'
variant rect1c_strip "$rect" "$centre"'m["planner_params"]={"max_flight_time_s":300,"subgraph_shape":"strip"}'
variant rect1c_strip_pen "$rect" "$centre"'m["planner_params"]={"max_flight_time_s":300,"subgraph_shape":"strip","turn_penalty_m":10}'
variant rect1c_pen "$rect" "$centre"'m["planner_params"]={"max_flight_time_s":300,"turn_penalty_m":10}'
if [[ "${RECT:-1}" == 1 ]]; then  # RECT=0: the 20 regions only
  for name in rect3 rect1 rect1_pen rect1_diag rect1c rect1c_pen rect1c_strip rect1c_strip_pen; do run "$name"; done
fi
for n in $rois; do
  roi="roi$(printf %02d "$((10#$n))")"
  variant "$roi" "$data/apostolidis2022/$roi.json" \
    "m[\"planner\"]=\"smt\"; m[\"mode\"]=\"$mode\"; m[\"battery_reserve\"]=0; m[\"planner_params\"]=json.loads(__import__(\"os\").environ[\"ROI_PARAMS\"])"
  run "$roi"
done

python3 - "$work" "$mode" "$rois" "$("$bin" --version)" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" <<'PY' | tee "$out"
import json, os, sys
work, mode, rois, version, cores, load = sys.argv[1:7]
def load_json(p):
    try:
        return json.load(open(p))
    except Exception:
        return None
def row(name):
    c = load_json(f"{work}/{name}/compare/compare.json")
    p = load_json(f"{work}/{name}/plan/plan.json")
    res = {}
    for e in (c or {}).get("planners", []):
        res[e["planner"]] = e
    d = (p or {}).get("planner_diagnostics", {})
    # the plan's battery sorties (one per route: each from home and back)
    d["_sorties"] = [st for u in (p or {}).get("uavs", []) for st in u.get("sorties", [])]
    return res, d
print("# SMT planner (POPCORN-style, z3) against DARP\n")
print(f"`bench/smt/run.sh`, {version}, Release build, measured on a {cores}-core machine shared with other "
      f"jobs (load average {load} at the end): compute times are wall-clock on a busy machine, not a clean "
      "measurement. One evaluator for both planners (`uavcover compare`: square footprint 1.5 ds swept along each "
      "leg, 1 m lattice). Length = coverage plus transit legs from and back to the start. Each smt route is an open path "
      "from its entry node to its exit node (a neighbour of the entry); its legs from and back to home are in the route "
      "times and route turns (plan diagnostics), and each route is one battery sortie of the plan from home and back (the plan's "
      "path returns home between routes; sortie times are eq. 15 with the evaluator's turn count, the route's "
      "coverage vertices).\n")
print("## Thesis rectangle (Table 5.3): 200 m x 100 m, ds 10 m, 3 m/s, 5-minute limit\n")
print("| run | planner | routes | sorties | PoC % | turns | coverage m | length m | route times s | sortie times s | route turns (with legs) | z3 subgraphs (optimal) | turn pairs | compute s |")
print("|---|---|---:|---:|---:|---:|---:|---:|---|---|---:|---|---:|---:|")
darp_done = set()
for name, label in [("rect3", "3 UAVs, seeded starts"), ("rect1", "1 UAV, home SW corner"),
                    ("rect1_pen", "1 UAV, home SW corner, turn penalty 10 m"),
                    ("rect1_diag", "1 UAV, home SW corner, 8-connected"),
                    ("rect1c", "1 UAV, home at the centre"),
                    ("rect1c_pen", "1 UAV, home at the centre, turn penalty 10 m"),
                    ("rect1c_strip", "1 UAV, home at the centre, strips"),
                    ("rect1c_strip_pen", "1 UAV, home at the centre, strips, turn penalty 10 m")]:
    res, d = row(name)
    for planner in ("smt", "darp"):
        e = res.get(planner)
        if not e:
            continue
        if planner == "smt":
            routes = d.get("route_count", "")
            times = ", ".join(f"{r['time_s']:.0f}" for r in d.get("routes", []))
            rturns = sum(r["turns"] for r in d.get("routes", []))
            sg = d.get("subgraphs", {})
            subs = f"{sg.get('count','')} ({sg.get('optimal','')})"
            pairs = sg.get("turn_pairs", "")
            nsorties = len(d["_sorties"])
            stimes = ", ".join(f"{60*st['duration_min']:.0f}" for st in d["_sorties"])
        else:
            # DARP does not depend on the smt parameters: one row per home point
            key = (name.startswith("rect1c"), name == "rect3")
            if key in darp_done:
                continue
            darp_done.add(key)
            routes, times, rturns, subs, pairs, nsorties, stimes = "", "", "", "", "", "", ""
        print(f"| {label} | {planner} | {routes} | {nsorties} | {100*e['poc']:.2f} | {e['turns']} | {e['coverage_length_m']:.0f} | "
              f"{e['length_m']:.0f} | {times} | {stimes} | {rturns} | {subs} | {pairs} | {e['compute_time_s']:.2f} |")
print("| thesis Table 5.3 | POPCORN | 3 | | | 116 | 1960 | | 210, 266, 256 | | | | | 7 |")
print("| thesis Table 5.3 | DARP (Java) | 3 | | | 51 | 2002 | | 262, 234, 252 | | | | | 3 |")
print(f"\n## The 20 regions of Apostolidis et al. 2022: 1 UAV, ds 40 m, {mode} mode, 25-minute limit\n")
print("| region | smt routes | smt PoC % | darp PoC % | smt turns | darp turns | smt length km | darp length km | smt compute s | darp compute s |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
sums = {"n": 0}
for n in rois.split():
    roi = f"roi{int(n):02d}"
    res, d = row(roi)
    s, dp = res.get("smt"), res.get("darp")
    if not s or not dp or not s.get("ok", True) or not dp.get("ok", True):
        print(f"| {roi} | failed | | | | | | | | |")
        continue
    r = d.get("route_count", "")
    print(f"| {roi} | {r} | {100*s['poc']:.2f} | {100*dp['poc']:.2f} | {s['turns']} | {dp['turns']} | "
          f"{s['length_m']/1000:.2f} | {dp['length_m']/1000:.2f} | {s['compute_time_s']:.2f} | {dp['compute_time_s']:.2f} |")
    sums["n"] += 1
    for k, v in [("sp", s["poc"]), ("dpp", dp["poc"]), ("st", s["turns"]), ("dt", dp["turns"]),
                 ("sl", s["length_m"]), ("dl", dp["length_m"]), ("sc", s["compute_time_s"]), ("dc", dp["compute_time_s"]),
                 ("sr", r if isinstance(r, int) else 0)]:
        sums[k] = sums.get(k, 0) + v
k = sums["n"]
if k:
    print(f"| mean of {k} | {sums['sr']/k:.2f} | {100*sums['sp']/k:.2f} | {100*sums['dpp']/k:.2f} | {sums['st']/k:.1f} | "
          f"{sums['dt']/k:.1f} | {sums['sl']/k/1000:.2f} | {sums['dl']/k/1000:.2f} | {sums['sc']/k:.2f} | {sums['dc']/k:.2f} |")
PY
echo "wrote $out" >&2
