#!/usr/bin/env bash
# Issue 4's streaming number: a 42 s / 0.25 deg sweep (100 scans of 721 beams, 72 100 points) streamed
# on the `cloud` topic to 10 clients that also take the pose stream, at time scale 1 in the G2 lobby;
# the pose rate each client gets must stay >= 45 Hz. mobot_stream_load plays the 10 browsers (raw
# WebSocket clients that timestamp every frame), so the numbers are the server's, not Chromium's.
# Usage: tests/bench/cloud_stream.sh [BUILD_DIR] [CLIENTS]   (default: build 10)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${1:-$ROOT/build}"
CLIENTS="${2:-10}"
WORK="$(mktemp -d)"
PID=""
trap '[ -n "$PID" ] && kill "$PID" 2>/dev/null; rm -rf "$WORK"' EXIT

"$BUILD/server/mobotd" --port 0 --data-dir "$WORK/var" --token bench --world g2_lobby \
  --log-level warn >"$WORK/out" 2>"$WORK/err" &
PID=$!
until grep -q "listening on" "$WORK/out" 2>/dev/null; do
  kill -0 "$PID" 2>/dev/null || { cat "$WORK/err"; exit 1; }
  sleep 0.01
done
PORT=$(sed -n 's/.*listening on http:\/\/[^:]*:\([0-9]*\).*/\1/p' "$WORK/out")

# The load tool connects, warms up 2 s and measures 44 s; the sweep starts 1 s into the window.
"$BUILD/tests/bench/mobot_stream_load" --port "$PORT" --token bench --clients "$CLIENTS" \
  --seconds 44 --warmup 2 --pid "$PID" --topics pose,cloud --encoding binary >"$WORK/load" &
LOAD=$!
sleep 3.5
curl -sf -X POST -H "Authorization: Bearer bench" "http://127.0.0.1:$PORT/api/v1/sweeps" \
  -d '{"period_s":42,"step_deg":0.25}' >/dev/null
wait "$LOAD" || echo "load tool reported failures"
cat "$WORK/load"
curl -sf -H "Authorization: Bearer bench" "http://127.0.0.1:$PORT/api/v1/sweeps/1" && echo
