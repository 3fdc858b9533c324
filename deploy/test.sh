#!/usr/bin/env bash
# Installs what is missing, builds everything, and runs every test: unit and API tests (CTest,
# each API test starts a real mobotd --backend sim --port 0), the dashboard's unit tests (Vitest)
# and the browser test (Debian's Chromium driven by playwright-core).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

"$ROOT/deploy/setup.sh"
"$ROOT/deploy/build.sh" --tests

echo "== unit and API tests"
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 300

echo "== reference results in the simulator (ALGORITHMS.md E1 UMBmark, E2 Table 3.3)"
build/tests/bench/mobot_umbmark
build/tests/bench/mobot_fusion_table

echo "== dashboard unit tests"
(cd web && npm test --silent)

echo "== browser test"
node tests/web/dashboard.test.mjs --mobotd "$ROOT/build/server/mobotd"

echo "== all tests passed"
