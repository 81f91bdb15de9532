#!/usr/bin/env bash
# The papers' tables rerun side by side with their published figures (issue 33), into
# bench/results/papers.md (dated, with the commit). One script, one file; SECTIONS picks what runs:
#   table3   Apostolidis 2022 Tables 3-5: the ablation of the placement objective's terms on the paper's 20
#            regions (Table 4 is region 6 of it, Table 5 region 15)
#   fig9     Apostolidis Fig. 9: turns with and without the turn-minimising tree orientation
#   study    Apostolidis Tables 7-10: the UAV-count study (1..15 UAVs) with the paper's time and cost model
#   thesis   Mondinelli 2025 Tables 5.1-5.3 (the rectangle, 3 UAVs) and 5.8-5.9 (60/40, both modes)
#   hong     Hong 2021 Tables 1-2: the joint MILP on polygons of 3 to 6 sides, 2 to 5 UAVs
#   spiral   Balampanis 2017 Tables I-IV: valley sensitivity and Lloyd steps on a coastal area
#
# Table 3: each variant plans the 20 regions of bench/data/apostolidis2022 (1 UAV, ds 40 m, strict mode)
# through bench/paper/run.sh (the CLI's `uavcover plan`, then `uavcover evaluate --lattice 1`, the one
# evaluator), with planner_params merged into every mission:
#   none      {"optimise_placement": false}                       the grid at shift 0, rotation 0
#   j1        {"objective": "paper", a 1, b 0, c 0}               the paper's J with J1 only
#   j12       {"objective": "paper", a 0.68, b 0.32, c 0}         J1 + J2
#   j123      {"objective": "paper", a 0.68, b 0.32, c 0.25}      J1 + J2 + J3, the paper's planner
#   ours      {} (defaults: objective "uavcover")                 our objective
# and each again with the suffix -raw: extend_legs and shift_legs off, the bare STC loops the paper flies;
# fig9 adds j123-raw-1tree and ours-1tree: min_turn_orientation off (one spanning-tree orientation).
# The inputs the papers do not publish are rebuilt as stand-ins by bench/papers/missions.py; papers.md says
# which.
#
# usage: bench/papers/run.sh [BUILD_DIR]     (default: build; or UAVCOVER=/path/to/uavcover)
# env:   WORK=/tmp/uavcover-papers  SECTIONS="table3 fig9 ..."  VARIANTS="none j1 ... ours-raw"
#        ROIS="01 02 ..."  OUT=...
# About 6 minutes on 2 cores (every plan runs under nice).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
data="$repo/bench/data/apostolidis2022"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-papers}"
sections="${SECTIONS:-table3 fig9 study thesis hong spiral}"
has() { [[ " $sections " == *" $1 "* ]]; }
variants="${VARIANTS:-}"
if [[ -z "$variants" ]]; then
  has table3 && variants="none j1 j12 j123 ours none-raw j1-raw j12-raw j123-raw ours-raw"
  has fig9 && variants="${variants:+$variants }j123-raw ours j123-raw-1tree ours-1tree"
  variants="$(tr ' ' '\n' <<<"$variants" | awk 'NF && !seen[$0]++' | tr '\n' ' ')"
fi
rois="${ROIS:-$(seq -w 1 20 | tr '\n' ' ')}"
out="${OUT:-$repo/bench/results/papers.md}"

[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin (build it, or pass BUILD_DIR / set UAVCOVER)" >&2; exit 2; }
[[ -f "$data/paper_results.csv" ]] || { echo "run.sh: benchmark data not found in $data" >&2; exit 2; }

params_of() {
  local v="$1" base p one=""
  [[ "$v" == *-1tree ]] && one=1 && v="${v%-1tree}"
  base="${v%-raw}"
  case "$base" in
    none) p='"optimise_placement": false' ;;
    j1) p='"objective": "paper", "j_weight_a": 1, "j_weight_b": 0, "j_weight_c": 0' ;;
    j12) p='"objective": "paper", "j_weight_a": 0.68, "j_weight_b": 0.32, "j_weight_c": 0' ;;
    j123) p='"objective": "paper", "j_weight_a": 0.68, "j_weight_b": 0.32, "j_weight_c": 0.25' ;;
    ours) p='' ;;
    *) echo "run.sh: unknown variant $1" >&2; exit 2 ;;
  esac
  [[ "$v" == *-raw ]] && p="${p:+$p, }\"extend_legs\": false, \"shift_legs\": false"
  [[ -n "$one" ]] && p="${p:+$p, }\"min_turn_orientation\": false"
  echo "{$p}"
}

mkdir -p "$work"
start=$(date +%s)
for v in $variants; do
  echo "== table 3: $v ($(params_of "$v"))" >&2
  # bench/paper/run.sh plans and evaluates; its own table goes to the scratch folder
  UAVCOVER="$bin" WORK="$work/table3/$v" MODES=strict ROIS="$rois" PARAMS="$(params_of "$v")" \
    OUT="$work/table3/$v.md" nice bash "$repo/bench/paper/run.sh" >/dev/null
done

plan_eval() {  # mission.json dir [plan options...]: plan, then the one evaluator at a 1 m lattice
  local m="$1" d="$2"; shift 2
  rm -rf "$d"
  nice "$bin" -q plan "$m" --out "$d" --no-images "$@"
  nice "$bin" -q evaluate "$m" "$d/paths.geojson" --out "$d" --lattice 1 --no-images
}

if has study; then
  # Tables 7-10: the paper's testbeds #3 (222 720 m2) and #4 (1 814 063 m2) are not published; stand-ins
  # of the same free areas: ROI 13 and ROI 11 scaled about their centroids
  mkdir -p "$work/study"
  for t in "3 13 222720" "4 11 1814063"; do
    read -r tb roi area <<<"$t"
    echo "== study: testbed $tb (roi$roi scaled to $area m2)" >&2
    python3 "$here/missions.py" testbed "$data/roi$roi.json" "$area" "$work/study/testbed$tb.json"
    rm -rf "$work/study/testbed$tb"
    nice "$bin" -q study "$work/study/testbed$tb.json" --uavs 1,2,3,5,7,9,12,15 --no-images \
      --out "$work/study/testbed$tb"
  done
fi

if has thesis; then
  echo "== thesis: the rectangle (Tables 5.1-5.3) and the 60/40 field (Tables 5.8-5.9)" >&2
  mkdir -p "$work/thesis"
  # the thesis's trajectory limits: 4 m/s^2 (its v_max 5 m/s is above the 3 m/s mean speed flown)
  python3 -c 'import json,sys; m=json.load(open(sys.argv[1]))
for u in m["uavs"]: u["max_accel_mps2"]=4
json.dump(m,open(sys.argv[2],"w"),indent=1)' "$repo/bench/data/mondinelli2025/rectangle_3uav.json" \
    "$work/thesis/rectangle.json"
  plan_eval "$work/thesis/rectangle.json" "$work/thesis/rectangle"
  rm -rf "$work/thesis/rectangle-export"
  nice "$bin" -q export "$work/thesis/rectangle" --format trajectory --out "$work/thesis/rectangle-export"
  for mode in strict coverage; do
    python3 "$here/missions.py" thesis-6040 "$mode" "$work/thesis/field6040-$mode.json"
    plan_eval "$work/thesis/field6040-$mode.json" "$work/thesis/field6040-$mode"
  done
fi

if has hong; then
  echo "== hong: polygons of 3 to 6 sides, 2 to 5 UAVs (Tables 1-2)" >&2
  mkdir -p "$work/hong"
  for sides in 3 4 5 6; do
    for uavs in 2 3 4 5; do
      python3 "$here/missions.py" hong "$sides" "$uavs" "$work/hong/p${sides}u$uavs.json"
      rm -rf "$work/hong/p${sides}u$uavs"
      nice "$bin" -q plan "$work/hong/p${sides}u$uavs.json" --out "$work/hong/p${sides}u$uavs" --no-images \
        --no-evaluate
    done
  done
fi

if has spiral; then
  echo "== spiral: valley sensitivity 2..5 and Lloyd 10/60/100 on a coastal bay (Tables I-IV)" >&2
  mkdir -p "$work/spiral"
  python3 "$repo/bench/spiral/coastline.py" "$work/spiral/bay.json" spiral 20 100
  for v in "2 10" "3 10" "4 10" "5 10" "6 10" "6 30" "6 60" "2 60" "2 100"; do
    read -r s l <<<"$v"
    python3 -c 'import json,sys; m=json.load(open(sys.argv[1]))
m["planner_params"]={"valley_sensitivity": float(sys.argv[2]), "lloyd_iterations": int(sys.argv[3])}
json.dump(m,open(sys.argv[4],"w"),indent=1)' "$work/spiral/bay.json" "$s" "$l" "$work/spiral/v$s-l$l.json"
    rm -rf "$work/spiral/v$s-l$l"
    nice "$bin" -q plan "$work/spiral/v$s-l$l.json" --out "$work/spiral/v$s-l$l" --no-images --no-evaluate
  done
fi
elapsed=$(( $(date +%s) - start ))

commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
git -C "$repo" diff --quiet HEAD -- src include bench ':!bench/results' 2>/dev/null || commit="$commit+changes"
mkdir -p "$(dirname "$out")"
{
  python3 "$here/table.py" "$data/paper_results.csv" "$work/table3" "$variants" "$rois" "$commit" \
    "$("$bin" --version 2>/dev/null || echo uavcover)" "$elapsed"
  python3 "$here/more.py" "$work" "$sections"
} >"$out"
cat "$out"
echo "wrote $out" >&2
