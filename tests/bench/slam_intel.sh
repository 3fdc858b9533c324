#!/usr/bin/env bash
# docs/algorithms.md E5 benchmark: mobot-slam on the noisy Intel log and on seeded noisy copies of
# the corrected log (mobot-carmen-noise), with fixed parameters. Prints per log the ATE against the
# reference trajectory, wall time, real-time factor and peak RSS; exits non-zero when any ATE is
# 0.10 m or more (or a run fails).
#
#   tests/bench/slam_intel.sh BUILD_DIR [DATA_DIR] [SEEDS...]
#
# DATA_DIR holds intel-noisy.log.gz, intel-corrected.log.gz and intel-gt.txt (default: the shared
# data directory beside the repository, ../shared/data). SEEDS default to 1 2 3 4 5.
set -euo pipefail

if [[ $# -lt 1 ]]; then
  echo "usage: $0 BUILD_DIR [DATA_DIR] [SEEDS...]" >&2
  exit 2
fi
build_dir=$(cd "$1" && pwd)
repo_dir=$(cd "$(dirname "$0")/../.." && pwd)
data_dir=${2:-$repo_dir/../shared/data}
shift $(( $# >= 2 ? 2 : 1 ))
seeds=("$@")
[[ ${#seeds[@]} -gt 0 ]] || seeds=(1 2 3 4 5)
max_ate_m=0.10

slam=$build_dir/tools/mobot-slam
noise=$build_dir/tools/mobot-carmen-noise
for tool in "$slam" "$noise"; do
  if [[ ! -x $tool ]]; then
    echo "$tool is missing: build the targets mobot_slam_tool and mobot_carmen_noise_tool" >&2
    exit 2
  fi
done
for file in intel-noisy.log.gz intel-corrected.log.gz intel-gt.txt; do
  if [[ ! -r $data_dir/$file ]]; then
    echo "the Intel data set is missing: $data_dir/$file not found (pass DATA_DIR as 2nd argument)" >&2
    exit 2
  fi
done
if [[ ! -x /usr/bin/time ]]; then
  echo "/usr/bin/time is needed for the peak RSS" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

failed=0
printf '%-22s %9s %8s %8s %9s %6s\n' log ATE_m wall_s RTF RSS_MB loops
run() {
  local name=$1 log=$2
  local out=$work/$name
  if ! /usr/bin/time -f '%M' -o "$work/$name.rss" "$slam" --carmen "$log" --out "$out" \
      --gt "$data_dir/intel-gt.txt" >"$work/$name.txt" 2>"$work/$name.err"; then
    echo "$name: mobot-slam failed:" >&2
    cat "$work/$name.err" >&2
    failed=1
    return
  fi
  local ate wall rtf rss loops
  ate=$(awk '/^ATE/ {print $2}' "$work/$name.txt")
  wall=$(awk '/^log/ {print $5}' "$work/$name.txt")
  rtf=$(awk '/^log/ {print $9}' "$work/$name.txt")
  loops=$(awk '/^scans/ {print $6}' "$work/$name.txt")
  rss=$(awk '{printf "%.1f", $1 / 1024}' "$work/$name.rss")
  printf '%-22s %9s %8s %8s %9s %6s\n' "$name" "$ate" "$wall" "$rtf" "$rss" "$loops"
  if ! awk -v a="$ate" -v m="$max_ate_m" 'BEGIN { exit !(a < m) }'; then
    echo "$name: ATE $ate m is not below $max_ate_m m" >&2
    failed=1
  fi
}

run intel-noisy "$data_dir/intel-noisy.log.gz"
for seed in "${seeds[@]}"; do
  "$noise" --in "$data_dir/intel-corrected.log.gz" --seed "$seed" \
    --out "$work/seed$seed.log" >/dev/null
  run "intel-seed$seed" "$work/seed$seed.log"
done
run intel-corrected "$data_dir/intel-corrected.log.gz"

if [[ $failed -ne 0 ]]; then
  echo "FAIL: an ATE reached $max_ate_m m or a run failed" >&2
  exit 1
fi
echo "PASS: every ATE below $max_ate_m m"
