#!/usr/bin/env bash
# Reference point for mobot-slam (tests/bench/slam_intel.sh): MRPT's icp-slam on the Intel Research
# Lab laser log, scored the same way (ATE = position RMSE of the per-scan estimates after the best
# rigid 2D alignment onto intel-gt.txt). Installs mrpt-apps from Debian when icp-slam is missing
# (needs root), rewrites each CARMEN log so MRPT 2.5's carmen2rawlog reads it right
# (mrpt_carmen_prep.py says why), converts it, runs icp-slam headless and prints per log the ATE,
# the ATE of the odometry alone, wall and user CPU time and peak RSS of icp-slam.
#
#   tests/bench/mrpt_icp_slam.sh [DATA_DIR] [INI]
#
# DATA_DIR holds intel-noisy.log.gz, intel-corrected.log.gz and intel-gt.txt (default: the shared
# data directory beside the repository, ../shared/data). INI defaults to
# tests/bench/mrpt_icp_slam.ini (its logOutput_dir is replaced by a temporary directory).
# Optional environment: NOISE_TOOL=path/to/mobot-carmen-noise and SEEDS="1 2 3" also run seeded
# noisy copies of the corrected log, as slam_intel.sh does. KEEP=DIR keeps the per-scan poses
# (DIR/NAME.poses.txt: `k x y yaw`) and icp-slam's output there.
# Exit status: 0 when every run finished (no ATE threshold), 1 when one failed, 2 on bad setup.
set -euo pipefail

repo_dir=$(cd "$(dirname "$0")/../.." && pwd)
here=$repo_dir/tests/bench
data_dir=${1:-$repo_dir/../shared/data}
ini=${2:-$here/mrpt_icp_slam.ini}
seeds=(${SEEDS:-})

for file in intel-noisy.log.gz intel-corrected.log.gz intel-gt.txt; do
  if [[ ! -r $data_dir/$file ]]; then
    echo "the Intel data set is missing: $data_dir/$file not found (pass DATA_DIR)" >&2
    exit 2
  fi
done
if [[ ! -r $ini ]]; then
  echo "$ini not found" >&2
  exit 2
fi
if [[ ${#seeds[@]} -gt 0 && ! -x ${NOISE_TOOL:-} ]]; then
  echo "SEEDS given but NOISE_TOOL (mobot-carmen-noise) is not an executable" >&2
  exit 2
fi

# mrpt-apps (icp-slam, carmen2rawlog) and GNU time, from Debian's packages when missing.
missing=()
command -v icp-slam >/dev/null && command -v carmen2rawlog >/dev/null || missing+=(mrpt-apps)
[[ -x /usr/bin/time ]] || missing+=(time)
if [[ ${#missing[@]} -gt 0 ]]; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "missing ${missing[*]}: install them (apt-get install ${missing[*]}) or run as root" >&2
    exit 2
  fi
  echo "installing ${missing[*]} ..." >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >/dev/null
  apt-get install -y -qq "${missing[@]}" >/dev/null
fi
mrpt_version=$(dpkg-query -W -f='${Version}' mrpt-apps 2>/dev/null || echo unknown)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
gt=$data_dir/intel-gt.txt

failed=0
echo "MRPT icp-slam $mrpt_version, config $ini"
printf '%-18s %8s %8s %8s %8s %8s\n' log ATE_m odoATE_m wall_s user_s RSS_MB
run() {
  local name=$1 log=$2
  local d=$work/$name
  mkdir -p "$d"
  # 1. CARMEN -> CARMEN that MRPT 2.5 parses right -> rawlog (odometry + scan per FLASER line).
  if ! python3 "$here/mrpt_carmen_prep.py" "$log" "$d/in.log" 2>"$d/prep.err" ||
     ! carmen2rawlog -q -w -i "$d/in.log" -o "$d/in.rawlog" >"$d/convert.txt" 2>&1; then
    echo "$name: conversion failed:" >&2
    cat "$d/prep.err" "$d/convert.txt" >&2
    failed=1
    return
  fi
  # 2. The ini with our output directory (icp-slam empties that directory first).
  sed -E "s|^[[:space:]]*logOutput_dir[[:space:]]*=.*|logOutput_dir = $d/out|" "$ini" >"$d/run.ini"
  grep -qF "logOutput_dir = $d/out" "$d/run.ini" || {
    echo "$ini has no logOutput_dir line in [MappingApplication]" >&2
    exit 2
  }
  # 3. icp-slam, timed.
  if ! /usr/bin/time -f '%e %U %M' -o "$d/time" icp-slam "$d/run.ini" "$d/in.rawlog" \
      >"$d/icp.out" 2>"$d/icp.err" </dev/null; then
    echo "$name: icp-slam failed:" >&2
    tail -20 "$d/icp.err" >&2
    failed=1
    return
  fi
  # 4. ATE of icp-slam's per-scan estimates and of the odometry it integrated.
  local ate odo wall user rss
  ate=$(python3 "$here/mrpt_ate.py" "$d/out/log_estimated_path.txt" "$gt" \
        --out "$d/poses.txt" | awk '{print $2}')
  odo=$(python3 "$here/mrpt_ate.py" "$d/out/log_odometry_path.txt" "$gt" | awk '{print $2}')
  read -r wall user rss <"$d/time"
  printf '%-18s %8s %8s %8s %8s %8.1f\n' "$name" "$ate" "$odo" "$wall" "$user" \
    "$(awk -v k="$rss" 'BEGIN { print k / 1024 }')"
  if [[ -n ${KEEP:-} ]]; then
    mkdir -p "$KEEP"
    cp "$d/poses.txt" "$KEEP/$name.poses.txt"
    rm -rf "${KEEP:?}/$name.out"
    cp -r "$d/out" "$KEEP/$name.out"
  fi
}

run intel-noisy "$data_dir/intel-noisy.log.gz"
for seed in "${seeds[@]}"; do
  "$NOISE_TOOL" --in "$data_dir/intel-corrected.log.gz" --seed "$seed" \
    --out "$work/seed$seed.log" >/dev/null
  run "intel-seed$seed" "$work/seed$seed.log"
done
run intel-corrected "$data_dir/intel-corrected.log.gz"

if [[ $failed -ne 0 ]]; then
  echo "FAIL: a run failed" >&2
  exit 1
fi
