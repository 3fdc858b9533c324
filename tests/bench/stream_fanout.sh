#!/usr/bin/env bash
# Server numbers of BENCHMARKS.md: start-up time, idle CPU and RSS at time scale 1, then the stream
# fan-out (pose 50 Hz + scan 40 Hz binary, 361 ranges) to N clients measured by mobot_stream_load.
# Usage: tests/bench/stream_fanout.sh [BUILD_DIR] [N ...]   (default: build 100 300 1000)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${1:-$ROOT/build}"
shift || true
CLIENTS=("${@:-100 300 1000}")
read -r -a CLIENTS <<<"${CLIENTS[*]}"
MOBOTD="$BUILD/server/mobotd"
LOAD="$BUILD/tests/bench/mobot_stream_load"
WORK="$(mktemp -d)"
trap 'kill "$PID" 2>/dev/null || true; rm -rf "$WORK"' EXIT

sed -e 's/^\(  laser_rate_hz:\).*/\1 40/' "$ROOT/deploy/config/default.yaml" >"$WORK/bench.yaml"
ulimit -n 65536 2>/dev/null || true

start_ns=$(date +%s%N)
"$MOBOTD" --config "$WORK/bench.yaml" --port 0 --data-dir "$WORK/var" --token bench \
  --log-level warn >"$WORK/out" 2>"$WORK/err" &
PID=$!
until grep -q "listening on" "$WORK/out" 2>/dev/null; do sleep 0.005; done
ready_ms=$((($(date +%s%N) - start_ns) / 1000000))
PORT=$(sed -n 's/.*listening on http:\/\/[^:]*:\([0-9]*\).*/\1/p' "$WORK/out")
echo "ready_ms $ready_ms"

cpu_s() { awk '{print ($14 + $15) / 100}' "/proc/$PID/stat"; }
sleep 2
before=$(cpu_s)
sleep 10
after=$(cpu_s)
echo "idle_cpu_pct_of_one_core $(awk -v a="$after" -v b="$before" 'BEGIN{printf "%.2f", (a-b)*10}')"
echo "idle_rss_mb $(awk '/VmRSS/{printf "%.1f", $2/1024}' "/proc/$PID/status")"

for n in "${CLIENTS[@]}"; do
  echo "== $n clients"
  "$LOAD" --port "$PORT" --token bench --clients "$n" --seconds 10 --warmup 2 --pid "$PID" \
    --topics pose,scan --encoding binary || echo "load tool reported failures"
  echo "rss_mb $(awk '/VmRSS/{printf "%.1f", $2/1024}' "/proc/$PID/status")"
  sleep 2
done
