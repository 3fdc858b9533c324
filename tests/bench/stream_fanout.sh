#!/usr/bin/env bash
# Server numbers of BENCHMARKS.md: start-up time, idle CPU and RSS at time scale 1, then the stream
# fan-out (pose 50 Hz + scan 40 Hz binary, 361 ranges) to N clients measured by mobot_stream_load.
# Usage: tests/bench/stream_fanout.sh [BUILD_DIR] [N ...]   (default: build 100 300 1000)
# REPEAT=3 runs each N three times (a fresh server each time) and ends with the median of each
# figure per N. Other processes' CPU during a run ("others") is printed: on a shared machine, a run
# where it is not near 0 measured the neighbours as much as mobotd.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${1:-$ROOT/build}"
shift || true
CLIENTS=("${@:-100 300 1000}")
read -r -a CLIENTS <<<"${CLIENTS[*]}"
REPEAT="${REPEAT:-1}"
MOBOTD="$BUILD/server/mobotd"
LOAD="$BUILD/tests/bench/mobot_stream_load"
WORK="$(mktemp -d)"
PID=""
trap '[ -n "$PID" ] && kill "$PID" 2>/dev/null; rm -rf "$WORK"' EXIT

sed -e 's/^\(  laser_rate_hz:\).*/\1 40/' "$ROOT/deploy/config/default.yaml" >"$WORK/bench.yaml"
ulimit -n 65536 2>/dev/null || true

start_server() {
  rm -rf "$WORK/var"
  local start_ns
  start_ns=$(date +%s%N)
  "$MOBOTD" --config "$WORK/bench.yaml" --port 0 --data-dir "$WORK/var" --token bench \
    --log-level warn >"$WORK/out" 2>"$WORK/err" &
  PID=$!
  until grep -q "listening on" "$WORK/out" 2>/dev/null; do
    kill -0 "$PID" 2>/dev/null || { cat "$WORK/err"; exit 1; }
    sleep 0.005
  done
  READY_MS=$((($(date +%s%N) - start_ns) / 1000000))
  PORT=$(sed -n 's/.*listening on http:\/\/[^:]*:\([0-9]*\).*/\1/p' "$WORK/out")
}

stop_server() {
  kill "$PID" 2>/dev/null || true
  wait "$PID" 2>/dev/null || true
  PID=""
}

cpu_s() { awk '{print ($14 + $15) / 100}' "/proc/$PID/stat"; }
# Busy and total jiffies of the whole machine.
machine() { awk '/^cpu /{print $2 + $3 + $4 + $7 + $8, $2 + $3 + $4 + $5 + $6 + $7 + $8}' /proc/stat; }
cores=$(nproc)

start_server
echo "ready_ms $READY_MS"
sleep 2
before=$(cpu_s)
sleep 10
after=$(cpu_s)
echo "idle_cpu_pct_of_one_core $(awk -v a="$after" -v b="$before" 'BEGIN{printf "%.2f", (a-b)*10}')"
echo "idle_rss_mb $(awk '/VmRSS/{printf "%.1f", $2/1024}' "/proc/$PID/status")"

: >"$WORK/summary"
for n in "${CLIENTS[@]}"; do
  for run in $(seq 1 "$REPEAT"); do
    [ -n "$PID" ] || { start_server; sleep 2; }
    echo "== $n clients, run $run/$REPEAT, $(sed 's/^\([^ ]* [^ ]* [^ ]*\).*/load average \1/' /proc/loadavg)"
    read -r busy_before total_before < <(machine)
    "$LOAD" --port "$PORT" --token bench --clients "$n" --seconds 10 --warmup 2 --pid "$PID" \
      --topics pose,scan --encoding binary | tee "$WORK/run" || echo "load tool reported failures"
    read -r busy_after total_after < <(machine)
    # The machine's busy time over connect + warm-up + window, less mobotd's and the tool's.
    others=$(awk -v b=$((busy_after - busy_before)) -v t=$((total_after - total_before)) \
      -v c="$cores" -v s="$(awk '/^server_cpu/{print $2}' "$WORK/run")" \
      -v l="$(awk '/^load_tool/{print $2}' "$WORK/run")" \
      'BEGIN{o = 100 * c * b / t - s - l; printf "%.1f", o < 0 ? 0 : o}')
    echo "others_cpu_pct_of_one_core $others (approximate: includes connecting and warm-up)"
    echo "rss_mb $(awk '/VmRSS/{printf "%.1f", $2/1024}' "/proc/$PID/status")"
    awk -v n="$n" '/^topic/{lat[$2] = $13 " " $15; lost += $8}
      /^server_cpu/{s = $2} /^load_tool/{l = $2}
      END{print n, lat["pose"], lat["scan"], lost, s, l}' "$WORK/run" >>"$WORK/summary"
    # A fresh server for the next run, so that runs do not share a warmed-up or degraded state.
    [ "$REPEAT" -gt 1 ] && stop_server
    sleep 2
  done
done

if [ "$REPEAT" -gt 1 ]; then
  echo "== median of $REPEAT runs: N pose_p50 pose_p99 scan_p50 scan_p99 lost server_cpu tool_cpu"
  for n in "${CLIENTS[@]}"; do
    line="$n"
    for column in 2 3 4 5 6 7 8; do
      line+=" $(awk -v n="$n" -v c="$column" '$1 == n {print $c}' "$WORK/summary" | sort -g |
        awk '{v[NR] = $1} END{print v[int((NR + 1) / 2)]}')"
    done
    echo "median $line"
  done
fi
