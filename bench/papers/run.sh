#!/usr/bin/env bash
# The papers' tables rerun side by side with their published figures (issue 33), into
# bench/results/papers.md (dated, with the commit). Today: Apostolidis et al. 2022, Table 3 (the ablation
# of the placement objective's terms on the paper's 20 regions).
#
# Table 3: each variant plans the 20 regions of bench/data/apostolidis2022 (1 UAV, ds 40 m, strict mode)
# through bench/paper/run.sh (the CLI's `uavcover plan`, then `uavcover evaluate --lattice 1`, the one
# evaluator), with planner_params merged into every mission:
#   none      {"optimise_placement": false}                       the grid at shift 0, rotation 0
#   j1        {"objective": "paper", a 1, b 0, c 0}               the paper's J with J1 only
#   j12       {"objective": "paper", a 0.68, b 0.32, c 0}         J1 + J2
#   j123      {"objective": "paper", a 0.68, b 0.32, c 0.25}      J1 + J2 + J3, the paper's planner
#   ours      {} (defaults: objective "uavcover")                 our objective
# and each again with the suffix -raw: extend_legs and shift_legs off, the bare STC loops the paper flies.
#
# usage: bench/papers/run.sh [BUILD_DIR]     (default: build; or UAVCOVER=/path/to/uavcover)
# env:   WORK=/tmp/uavcover-papers  VARIANTS="none j1 ... ours-raw"  ROIS="01 02 ..."  OUT=...
# About 3 minutes on 2 cores (every plan runs under nice).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="${1:-$repo/build}"
bin="${UAVCOVER:-$build/uavcover}"
data="$repo/bench/data/apostolidis2022"
work="${WORK:-${TMPDIR:-/tmp}/uavcover-papers}"
variants="${VARIANTS:-none j1 j12 j123 ours none-raw j1-raw j12-raw j123-raw ours-raw}"
rois="${ROIS:-$(seq -w 1 20 | tr '\n' ' ')}"
out="${OUT:-$repo/bench/results/papers.md}"

[[ -x "$bin" ]] || { echo "run.sh: no uavcover binary at $bin (build it, or pass BUILD_DIR / set UAVCOVER)" >&2; exit 2; }
[[ -f "$data/paper_results.csv" ]] || { echo "run.sh: benchmark data not found in $data" >&2; exit 2; }

params_of() {
  local base="${1%-raw}" p
  case "$base" in
    none) p='"optimise_placement": false' ;;
    j1) p='"objective": "paper", "j_weight_a": 1, "j_weight_b": 0, "j_weight_c": 0' ;;
    j12) p='"objective": "paper", "j_weight_a": 0.68, "j_weight_b": 0.32, "j_weight_c": 0' ;;
    j123) p='"objective": "paper", "j_weight_a": 0.68, "j_weight_b": 0.32, "j_weight_c": 0.25' ;;
    ours) p='' ;;
    *) echo "run.sh: unknown variant $1" >&2; exit 2 ;;
  esac
  [[ "$1" == *-raw ]] && p="${p:+$p, }\"extend_legs\": false, \"shift_legs\": false"
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
elapsed=$(( $(date +%s) - start ))

commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
git -C "$repo" diff --quiet HEAD -- src include bench 2>/dev/null || commit="$commit+changes"
mkdir -p "$(dirname "$out")"
python3 "$here/table.py" "$data/paper_results.csv" "$work/table3" "$variants" "$rois" "$commit" \
  "$("$bin" --version 2>/dev/null || echo uavcover)" "$elapsed" >"$out"
cat "$out"
echo "wrote $out" >&2
