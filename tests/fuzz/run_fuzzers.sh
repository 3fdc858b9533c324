#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build (cmake -DMOBOT_FUZZ=ON with clang++) for a bounded
# time or number of inputs, keeping each target's corpus in the build tree so later runs start
# from what earlier ones found; the seeds of tests/fuzz/corpus/TARGET (valid inputs) are read too,
# never written. Exits non-zero on the first crash, leak or sanitizer report.
#   tests/fuzz/run_fuzzers.sh BUILD_DIR -max_total_time=20
#   tests/fuzz/run_fuzzers.sh BUILD_DIR -runs=1000000
set -euo pipefail
BUILD_DIR="$1"
shift
SEEDS_DIR="$(cd "$(dirname "$0")" && pwd)/corpus"
for target in "$BUILD_DIR"/fuzz/fuzz_*; do
  name="$(basename "$target")"
  corpus="$BUILD_DIR/corpus/$name"
  mkdir -p "$corpus"
  seeds=()
  if [[ -d "$SEEDS_DIR/$name" ]]; then seeds=("$SEEDS_DIR/$name"); fi
  log="$BUILD_DIR/$name.log"
  if ! "$target" "$corpus" "${seeds[@]}" -artifact_prefix="$BUILD_DIR/$name-" -print_final_stats=1 \
      "$@" >"$log" 2>&1; then
    echo "fuzz: $name FAILED (log: $log)" >&2
    tail -40 "$log" >&2
    exit 1
  fi
  runs="$(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')"
  echo "fuzz: $name: $runs inputs, 0 crashes"
done
