#!/usr/bin/env bash
# docs/algorithms.md E4 on the Intel Research Lab log: mobot-slam builds the map from the corrected
# log (the reference poses), then mobot_localization_intel runs the particle filter on the noisy
# odometry log, tracking from a start 1 m / 30 deg off and globally, and scores both against the
# trajectory the map was built from and the reference (exit 0 only when both converge with a
# position RMSE below 0.05 m against the map's trajectory).
# Usage: tests/bench/localization_intel.sh BUILD DATA_DIR
#   DATA_DIR holds intel-corrected.log.gz, intel-noisy.log.gz and intel-gt.txt.
# Exit status: the tool's (0 pass, 1 fail); 2 when mobot-slam or the tool is not built or the data
# is missing.
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 BUILD DATA_DIR" >&2
  exit 2
fi
BUILD="$1"
DATA="$2"
SLAM="$BUILD/tools/mobot-slam"
TOOL="$BUILD/tests/bench/mobot_localization_intel"
if [ ! -x "$SLAM" ]; then
  echo "$SLAM is not built (cmake --build $BUILD --target mobot_slam_tool); no map, no run" >&2
  exit 2
fi
if [ ! -x "$TOOL" ]; then
  echo "$TOOL is not built (cmake --build $BUILD --target mobot_localization_intel)" >&2
  exit 2
fi
for f in intel-corrected.log.gz intel-noisy.log.gz intel-gt.txt; do
  if [ ! -r "$DATA/$f" ]; then
    echo "$DATA/$f is missing" >&2
    exit 2
  fi
done
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

"$SLAM" --carmen "$DATA/intel-corrected.log.gz" --out "$WORK/map"
# The gate is the RMSE against the poses mobot-slam built the map from: its map is itself a few
# centimetres off the reference, which the tool prints as well.
"$TOOL" --map "$WORK/map/map.yaml" --map-trajectory "$WORK/map/trajectory.txt" \
  --log "$DATA/intel-noisy.log.gz" --reference "$DATA/intel-gt.txt" --mode both
