#!/usr/bin/env bash
# Installs what is missing, builds, and starts mobotd with the simulated robot and the dashboard
# on http://127.0.0.1:8080. Extra arguments go to mobotd (e.g. --world g2_lobby --port 9000, or
# --config deploy/config/dashgo_d1.yaml --world office); --config and --data-dir replace the
# defaults below when given. The backend is the config's: the default config simulates R1, and
# --config deploy/config/dashgo_d1_hardware.yaml drives a real Dashgo D1.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

"$ROOT/deploy/setup.sh"
"$ROOT/deploy/build.sh"

given() {
  local flag="$1"
  shift
  for arg in "$@"; do
    if [[ "$arg" == "$flag" || "$arg" == "$flag="* ]]; then return 0; fi
  done
  return 1
}
defaults=()
given --config "$@" || defaults+=(--config "$ROOT/deploy/config/default.yaml")
given --data-dir "$@" || defaults+=(--data-dir "$ROOT/var")
exec "$ROOT/build/server/mobotd" "${defaults[@]}" "$@"
