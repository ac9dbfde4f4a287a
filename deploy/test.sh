#!/usr/bin/env bash
# README command (b): set up, build, and run every test.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if [ "$(id -u)" -eq 0 ]; then bash deploy/setup.sh; else sudo bash deploy/setup.sh; fi
bash deploy/build.sh
ctest --test-dir "${DF_BUILD:-$root/build}" --output-on-failure -j "${DF_TEST_JOBS:-2}" --timeout 600
