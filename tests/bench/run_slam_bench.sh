#!/usr/bin/env bash
# SLAM benchmark (figures in docs/benchmarks.md): accuracy and per-stage speed of df_slam offline
# at full and at half processing resolution
#   - on real frames: 7-Scenes (300 frames, Kinect v1), side by side with Open3D's RGB-D
#     odometry (hybrid term, frame to frame) in the same run;
#   - on generated static scenes with sensor noise (static_xyz, static_halfsphere).
# usage: tests/bench/run_slam_bench.sh [7SCENES_FOLDER] [FRAMES_GENERATED]
# Needs a build (bash deploy/build.sh) and, for the peer, `bash deploy/setup.sh --bench`.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$root/build/bin"
scenes="${1:-$root/../shared/data/7scenes-300}"
generated_frames="${2:-300}"
out="$root/out/bench/slam"
mkdir -p "$out"
summary() {  # name folder
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
name, d = sys.argv[1], sys.argv[2]
s = json.load(open(f"{d}/summary.json"))
ate = json.load(open(f"{d}/ate.json"))
st = s["stages_ms"]
rmse = ate["ate"]["translation_m"]["rmse"]
tm = st["tracking"]["median"] + st["fusion"]["median"] + st["prediction"]["median"]
print(f"{name:34s} ATE {rmse*100:6.2f} cm  lost {s['lost']:3d}  "
      + "  ".join(f"{k} {v['median']:5.1f}/{v['p95']:5.1f}" for k, v in st.items())
      + f"  track+map median {tm:5.1f} ms  surfels {s['surfels']}  {s['map_bytes']/2**20:.0f} MiB")
PY
}
run_ours() {  # name folder preset downscale
  local dir="$out/$1"
  "$bin/df_slam" offline "$2" -o "$dir" ${3:+--preset $3} \
    --set "slam { system { processing_downscale: $4 } }" --set 'output { log_every: 0 }' \
    >"$dir.out" 2>"$dir.log" || { echo "df_slam failed, see $dir.log"; tail -3 "$dir.log"; return 1; }
  "$bin/df_eval" ate "$2/groundtruth.txt" "$dir/trajectory.txt" --json "$dir/ate.json" \
    --plot "$dir/ate.png" >/dev/null
  summary "$1" "$dir"
}
echo "per stage: median/p95 ms (2-core machine, $(nproc) threads)"
if [ -d "$scenes" ]; then
  run_ours "7scenes_full" "$scenes" 7scenes 1
  run_ours "7scenes_half" "$scenes" 7scenes 2
  if /usr/bin/python3 -c "import open3d" 2>/dev/null; then
    /usr/bin/python3 "$root/tests/bench/open3d_odometry.py" "$scenes" "$out/open3d_trajectory.txt" \
      | tee "$out/open3d.out"
    "$bin/df_eval" ate "$scenes/groundtruth.txt" "$out/open3d_trajectory.txt" \
      --plot "$out/open3d_ate.png" | grep -i rmse | head -1 | sed 's/^/open3d odometry: /'
  else
    echo "open3d not installed (bash deploy/setup.sh --bench): peer skipped"
  fi
else
  echo "no 7-Scenes folder at $scenes: real-data part skipped"
fi
for preset in static_xyz static_halfsphere; do
  seq="$out/seq_$preset"
  [ -f "$seq/groundtruth.txt" ] && [ "$(wc -l < "$seq/groundtruth.txt")" -ge "$generated_frames" ] ||
    "$bin/df_make_sequence" --preset $preset --frames "$generated_frames" --out "$seq" >/dev/null 2>&1
  run_ours "${preset}_full" "$seq" "" 1
  run_ours "${preset}_half" "$seq" "" 2
done
