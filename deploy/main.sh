#!/usr/bin/env bash
# README command (a): set up, build, and run the main job on the built-in default data:
# capture -> SLAM under the supervisor over shared memory, then the ATE against the sequence's
# ground truth and the frame rate. DF_DATA=<TUM folder> runs another sequence (fr3 intrinsics).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if [ "$(id -u)" -eq 0 ]; then bash deploy/setup.sh; else sudo bash deploy/setup.sh; fi
bash deploy/build.sh
export DF_OUT="${DF_OUT:-$root/out/main}"
export DF_DATA="${DF_DATA:-$root/build/data/default}"
run_dir="$DF_OUT/run"
slam_out="$DF_OUT/slam"
rm -rf "$slam_out"
deploy/dfsup --run-dir "$run_dir" up deploy/pipelines/default.pbtxt
trap 'deploy/dfsup --run-dir "$run_dir" down >/dev/null 2>&1 || true' EXIT
status=0
deploy/dfsup --run-dir "$run_dir" wait slam --timeout 900 || status=$?
deploy/dfsup --run-dir "$run_dir" wait fusion --timeout 60 || true
echo
echo "== $(basename "$DF_DATA"): capture -> slam, geoseg, detector (YOLOv5s), fusion; shared memory =="
grep -E "done:|bad frame" "$run_dir/logs/capture.log" | sed 's/^[^]]*\] //' || true
grep -E "stream ended" "$run_dir/logs/geoseg.log" "$run_dir/logs/detector.log" \
  "$run_dir/logs/fusion.log" | sed 's/^.*logs\///; s/\.log:[^]]*\] /: /' || true
grep -E "stream ended|tracking lost|recovered" "$run_dir/logs/slam.log" | sed 's/^[^]]*\] //' || true
if [ ! -s "$slam_out/trajectory.txt" ]; then
  echo "no trajectory was written; see $run_dir/logs/slam.log" >&2
  exit 1
fi
echo
if [ -f "$DF_DATA/groundtruth.txt" ]; then
  build/bin/df_eval ate "$DF_DATA/groundtruth.txt" "$slam_out/trajectory.txt" \
    --json "$slam_out/ate.json" --plot "$slam_out/ate.png" || status=$?
fi
/usr/bin/python3 - "$slam_out/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
st = s["stages_ms"]
print(f"frames {s['frames']} (tracked {s['tracked']}, lost {s['lost']}); "
      f"{s['fps']:.1f} frames/s end to end in lockstep")
print("SLAM per frame, median / p95 ms: " + ", ".join(
    f"{k} {v['median']:.1f} / {v['p95']:.1f}" for k, v in st.items()))
print(f"map: {s['surfels']} surfels ({s['stable_surfels']} stable), {s['map_bytes'] / 2**20:.1f} MiB")
PY
echo
echo "trajectory: $slam_out/trajectory.txt (TUM format)"
echo "map:        $slam_out/map.ply (open in MeshLab, CloudCompare or Open3D)"
echo "plots:      $slam_out/ate.png; figures: $slam_out/ate.json, $slam_out/summary.json"
echo "logs:       $run_dir/logs/"

# The static SLAM core above tracks everything it sees, moving objects included. Until the
# segmentation services exist, show what masks of the moving things buy: the same frames in
# one process with the sequence's ground-truth instance masks (simulated segmentation).
if [ -d "$DF_DATA/instances" ]; then
  masked_out="$DF_OUT/slam_gt_masks"
  rm -rf "$masked_out"
  echo
  echo "== the same frames with SIMULATED segmentation: ground-truth instance masks (df_slam offline --masks) =="
  if build/bin/df_slam offline "$DF_DATA" -o "$masked_out" --masks "$DF_DATA/instances" \
      >"$masked_out.log" 2>&1; then
    grep -E "^processed|^ATE" "$masked_out.log" || true
    echo "map: $masked_out/map.ply; log: $masked_out.log"
  else
    echo "the masked run failed; see $masked_out.log" >&2
    status=1
  fi
fi
exit $status
