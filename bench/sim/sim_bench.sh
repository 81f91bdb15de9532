#!/usr/bin/env bash
# Simulated vehicles per core: runs `uavcover simulate` with N vehicles flying the example plan's
# missions (--plan --autostart) at speedup x1 for 20 simulated (= wall) seconds, telemetry sent to a
# UDP sink, and reads the process's CPU time from /usr/bin/time -v.
# Usage: [SPEEDUP=K] bench/sim/sim_bench.sh [UAVCOVER_BINARY] [N...]   (default N: 50 100 200, K 1)
# With SPEEDUP=K the run is still 20 wall seconds (20*K simulated seconds).
set -euo pipefail
BIN=${1:-build/uavcover}
shift || true
COUNTS=${*:-50 100 200}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
"$BIN" -q plan examples/olive-grove.json -o "$WORK/plan"
PORT=47999
K=${SPEEDUP:-1}
SIM_S=$(python3 -c "print(20*$K)")
echo "| vehicles | speedup | simulated s | wall s | CPU s (user+sys) | CPU % of one core | vehicle-seconds simulated per CPU second (= vehicles per core at x1) | telemetry datagrams/s (sink) | max RSS MiB |"
echo "|---|---|---|---|---|---|---|---|---|"
for N in $COUNTS; do
  python3 - "$PORT" "$WORK/count.txt" 24 <<'PY' &
import socket, sys, time
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8 << 20)
s.bind(("127.0.0.1", int(sys.argv[1])))
s.settimeout(0.5)
n, end = 0, time.time() + float(sys.argv[3])
while time.time() < end:
    try:
        s.recv(2048); n += 1
    except socket.timeout:
        pass
open(sys.argv[2], "w").write(str(n))
PY
  SINK=$!
  sleep 0.5
  /usr/bin/time -v "$BIN" -q simulate --vehicles "$N" --listen udp:127.0.0.1:0 --plan "$WORK/plan" --autostart \
    --gcs "udp:127.0.0.1:$PORT" --speedup "$K" --duration "$SIM_S" --battery-min 100 > /dev/null 2> "$WORK/time.txt"
  wait "$SINK"
  user=$(awk -F': ' '/User time/{print $2}' "$WORK/time.txt")
  sys=$(awk -F': ' '/System time/{print $2}' "$WORK/time.txt")
  rss=$(awk -F': ' '/Maximum resident/{print $2}' "$WORK/time.txt")
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/{print $2}' "$WORK/time.txt" | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
  python3 -c "
u,s,n,r,c,w=$user,$sys,$N,$rss,$(cat "$WORK/count.txt"),$wall
cpu=u+s
print(f'| {n} | x$K | $SIM_S | {w:.1f} | {cpu:.2f} | {100*cpu/w:.1f} % | {n*$SIM_S/cpu:.0f} | {c/min(w,24):.0f} | {r/1024:.1f} |')"
done
