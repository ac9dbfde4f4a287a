#!/usr/bin/env bash
# Configures and builds DetectFusion into build/ (Release), then makes the built-in default data.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${DF_BUILD:-$root/build}"
jobs="${DF_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$jobs"
if [ ! -f "$build/data/default/associations.txt" ]; then
  "$build/bin/df_make_sequence" --preset default --out "$build/data/default"
fi
