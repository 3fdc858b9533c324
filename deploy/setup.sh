#!/usr/bin/env bash
# Installs what mobot needs to build, run and test, on Debian, as root. Idempotent and quiet when
# everything is already there: it only calls apt-get when a package is missing.
set -euo pipefail

DEB_PACKAGES=(
  build-essential cmake pkg-config git ca-certificates
  libboost-dev libeigen3-dev nlohmann-json3-dev libsqlite3-dev sqlite3 libssl-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-videoio-dev
  libopencv-video-dev
  libmodbus-dev
  libspdlog-dev libyaml-cpp-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-dev
  chromium
)

missing=()
for pkg in "${DEB_PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "ok installed"; then
    missing+=("$pkg")
  fi
done

# Node.js may come from Debian (nodejs + npm) or from another vendor's single nodejs package that
# bundles npm; only ask for Debian's when there is no working npm at all.
if ! command -v npm >/dev/null 2>&1; then
  missing+=(nodejs npm)
fi

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
fi
