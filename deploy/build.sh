#!/usr/bin/env bash
# Builds mobotd (and, with --tests, the tests and benchmarks) into build/ and the dashboard into
# web/dist. Used by run.sh and test.sh after setup.sh; safe to run again (incremental).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

with_tests=OFF
targets=(--target mobotd)
if [[ "${1:-}" == "--tests" ]]; then
  with_tests=ON
  targets=()
fi

jobs="$(nproc)"
mkdir -p build
if ! cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOBOT_BUILD_TESTS="$with_tests" \
    -DMOBOT_BUILD_BENCH="$with_tests" >build/cmake-configure.log 2>&1; then
  cat build/cmake-configure.log >&2
  exit 1
fi
cmake --build build -j"$jobs" "${targets[@]}"

# npm ci only when the lock file changed since the last install: it wipes node_modules.
npm_install() {
  local dir="$1"
  local stamp="$dir/node_modules/.mobot-lock-hash"
  local hash
  hash="$(sha256sum "$dir/package-lock.json" | cut -d' ' -f1)"
  if [[ ! -f "$stamp" || "$(cat "$stamp")" != "$hash" ]]; then
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
    echo "$hash" >"$stamp"
  fi
}
npm_install web
(cd web && npm run --silent build)
if [[ "$with_tests" == ON ]]; then
  npm_install tests/web
fi
