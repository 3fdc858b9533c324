#!/usr/bin/env bash
# Installs what is missing, builds, and starts mobotd with the simulated robot and the dashboard
# on http://127.0.0.1:8080 (extra arguments go to mobotd, e.g. --world g2_lobby --port 9000).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

"$ROOT/deploy/setup.sh"
"$ROOT/deploy/build.sh"
exec "$ROOT/build/server/mobotd" --config "$ROOT/deploy/config/default.yaml" --backend sim \
  --data-dir "$ROOT/var" "$@"
