#!/usr/bin/env bash
# Installs every dependency of DetectFusion on Debian 12, by package name.
# Run as root (or with sudo). Safe to run again: it only installs what is missing.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  cyclonedds-dev cyclonedds-tools iceoryx libiceoryx-binding-c-dev
  libeigen3-dev libopencv-dev libopenni2-dev
  libprotobuf-dev protobuf-compiler
  supervisor
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libcli11-dev libzstd-dev liblz4-dev libnanoflann-dev zlib1g-dev
  python3 python3-protobuf python3-numpy python3-matplotlib
  darknet
)
# Only for the benchmarks that compare with other systems (tests/bench/run_slam_bench.sh):
# `bash deploy/setup.sh --bench`.
if [ "${1:-}" = "--bench" ]; then
  APT_PACKAGES+=(python3-open3d)
fi

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing Debian packages: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "[setup] all Debian packages present"
fi

# Node.js + npm come preinstalled on these machines; Debian's npm conflicts with that build.
if ! command -v npm >/dev/null 2>&1; then
  echo "[setup] npm missing: installing Debian nodejs + npm"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq nodejs npm
fi

# npm packages used by tests (an independent MCAP reader) live under tests/js.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Reinstalled whenever package-lock.json changes (exact versions, no scripts run).
js="$here/tests/js"
if [ -f "$js/package-lock.json" ] && ! cmp -s "$js/package-lock.json" "$js/node_modules/.df-installed-lock"; then
  echo "[setup] installing npm packages for tests/js (@mcap/core, @foxglove/omgidl-*)"
  (cd "$js" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
  cp "$js/package-lock.json" "$js/node_modules/.df-installed-lock"
fi
echo "[setup] done"
