#!/usr/bin/env bash
# Issue 27's server measures on the 5 x 4 km field (bench/ondemand/field-5x4km.json, 8 UAVs, spacing
# 10 m), on the embedded SQLite database:
#   1. `uavcover plan FIELD` (plan, evaluation, pictures; no exports): wall time and RSS;
#   2. JOBS plan jobs through POST /missions/{id}/plans, one at a time: each job's wall time (the job's
#      own started -> finished) and how much the database (file + WAL) grew;
#   3. the first and the second request of every export format of the last plan (uav = the first
#      UAV), and the zip of them all is not built by the server (the web app builds it from these).
# usage: bench/ondemand/run.sh   environment: UAVCOVER_BIN (default build/uavcover), JOBS=3,
#        FIELD (mission file), SERVE_ARGS (extra `uavcover serve` options, e.g. "--keep-plans 10")
# Prints a Markdown table on stdout. Needs curl and python3.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${UAVCOVER_BIN:-$PWD/build/uavcover}
field=${FIELD:-$PWD/bench/ondemand/field-5x4km.json}
jobs=${JOBS:-3}
work=$(mktemp -d)
pid=""
cleanup() {
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT

json() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)"; }
dbsize() { du -cb "$work"/db* 2>/dev/null | tail -1 | cut -f1; }
mb() { python3 -c "print('%.2f' % ($1 / 1e6))"; }
load() { cut -d' ' -f1-3 /proc/loadavg; }

# 1. the CLI
/usr/bin/time -f "%e %M" -o "$work/time" "$bin" plan "$field" --out "$work/cli" >/dev/null 2>&1
read -r cli_s cli_kb <"$work/time"
echo "\`bench/ondemand/run.sh\` on $(basename "$field"), JOBS=$jobs${SERVE_ARGS:+, serve $SERVE_ARGS}, $(nproc) cores."
echo
echo "| measure | value | load average |"
echo "|---|---|---|"
echo "| \`uavcover plan\` (plan, evaluation, pictures) | ${cli_s} s, $((cli_kb / 1024)) MB RSS | $(load) |"

# 2. the server
port=$((20000 + RANDOM % 20000))
url=http://127.0.0.1:$port/api/v1
# shellcheck disable=SC2086
"$bin" serve --listen 127.0.0.1:$port --db "sqlite:$work/db" --workers 1 ${SERVE_ARGS:-} >"$work/log" 2>&1 &
pid=$!
for _ in $(seq 100); do curl -fs "http://127.0.0.1:$port/healthz" >/dev/null && break || sleep 0.1; done
mission=$(curl -fs -H 'Content-Type: application/json' --data-binary @"$field" "$url/missions" | json 'd["id"]')
before=$(dbsize)
plan=""
for k in $(seq "$jobs"); do
  plan=$(curl -fs -X POST "$url/missions/$mission/plans" | json 'd["id"]')
  while :; do
    state=$(curl -fs "$url/plans/$plan" | json 'd["state"]')
    case $state in done | failed | cancelled) break ;; esac
    sleep 0.2
  done
  wall=$(curl -fs "$url/plans/$plan" | python3 -c '
import json,sys,datetime
d=json.load(sys.stdin)
t=lambda s: datetime.datetime.fromisoformat(s.replace("Z","+00:00")).timestamp()
print("%.2f" % (t(d["finished"]) - t(d["started"])))')
  after=$(dbsize)
  # with many jobs only the first three and the last are shown
  if [ "$k" -le 3 ] || [ "$k" -eq "$jobs" ]; then
    echo "| plan job $k ($state): wall time, database growth | $wall s, $(mb $((after - before))) MB | $(load) |"
  fi
  before=$after
done
echo "| database after $jobs jobs (file + WAL) | $(mb "$(dbsize)") MB | $(load) |"

# 3. exports of the last plan
uav=$(curl -fs "$url/plans/$plan" | json 'd["result"]["uavs"][0]["id"]')
for f in qgc wpl kml kmz dji litchi csv geojson trajectory; do
  # a dropped connection is status 000 (curl fails): shown, not fatal
  first=$(curl -s -o "$work/x" -w '%{http_code} %{time_total}' "$url/plans/$plan/exports/$f?uav=$uav" || true)
  second=$(curl -s -o "$work/y" -w '%{time_total}' "$url/plans/$plan/exports/$f?uav=$uav" || true)
  same=$(cmp -s "$work/x" "$work/y" && echo same || echo DIFFERENT)
  echo "| export $f ($uav): first request (status, s), second (s) | $first, $second ($(stat -c %s "$work/x") bytes, $same) | $(load) |"
done
