#!/usr/bin/env bash
# Dynamic-SLAM benchmark (figures in docs/dynamics.md): df_slam offline, the whole system in one
# process, on generated sequences (300 frames, default seed) and on 7-Scenes, per detector:
#   yolov5     the real YOLOv5s (the main figures),
#   simulated  SIMULATED: boxes from the sequence's ground truth,
#   off        --dynamics off (the static core alone, for comparison).
# Prints one line per run: ATE RMSE, lost frames, the per-frame medians of tracking (both
# stages), motion segmentation, fusion and prediction, offline wall time per frame, and the mean
# fraction of the pixels motion segmentation looked at that it flagged as moving.
# usage: tests/bench/run_dynamic_bench.sh
# environment: PRESETS (default: the issue's seven and static_xyz, static_halfsphere; "" = none),
#   DETECTORS (default "yolov5 simulated off"), FRAMES (300), SCENES (7-Scenes folder; "" skips),
#   SET (extra --set for every run, e.g. 'slam { tracking { icp_weight: 1 } }'),
#   TAG (names the output folder out/bench/dynamic/TAG), MASKS=1 (also write the per-frame
#   masks, for df_eval seg), BIN (the binaries; default build/bin).
# Needs a build (bash deploy/build.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${BIN:-$root/build/bin}"
frames="${FRAMES:-300}"
presets="${PRESETS-walking_static walking_xyz walking_rpy walking_halfsphere sitting_xyz sitting_halfsphere default static_xyz static_halfsphere}"
detectors="${DETECTORS:-yolov5 simulated off}"
scenes="${SCENES-$root/../shared/data/7scenes-300}"
out="$root/out/bench/dynamic/${TAG:-default}"
seqs="$root/out/bench/dynamic/seqs"
mkdir -p "$out" "$seqs"
set_args=()
[ -n "${SET:-}" ] && set_args=(--set "$SET")

summary() {  # name dir
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
name, d = sys.argv[1], sys.argv[2]
s = json.load(open(f"{d}/summary.json"))
rmse = json.load(open(f"{d}/ate.json"))["ate"]["translation_m"]["rmse"]
st = s["stages_ms"]
med = lambda k: st[k]["median"] if k in st else 0.0
core = med("tracking") + med("fusion") + med("prediction")  # tracking includes motion
print(f"{name:34s} ATE {rmse*100:6.2f} cm  lost {s['lost']:3d}/{s['frames']:3d}  "
      f"tracking {med('tracking'):5.1f}  motion {med('motion'):4.1f}  fusion {med('fusion'):4.1f}  "
      f"prediction {med('prediction'):4.1f}  core {core:5.1f} ms  "
      f"wall {1000.0 / s['fps'] if s.get('fps') else float('nan'):6.1f} ms/frame"
      + (f"  flagged {100 * s['motion_fraction']['mean']:.3f} %" if "motion_fraction" in s else ""),
      flush=True)
PY
}
run() {  # name folder detector [preset]
  local dir="$out/$1" args=()
  case "$3" in
    off) args=(--dynamics off) ;;
    *) args=(--detector "$3") ;;
  esac
  "$bin/df_slam" offline "$2" -o "$dir" ${4:+--preset $4} "${args[@]}" --write-masks "$([ "${MASKS:-0}" = 1 ] && echo true || echo false)" \
    --set 'output { log_every: 0 }' "${set_args[@]}" >"$dir.out" 2>"$dir.log" \
    || { echo "$1: df_slam failed, see $dir.log"; tail -3 "$dir.log"; return 0; }
  "$bin/df_eval" ate "$2/groundtruth.txt" "$dir/trajectory.txt" --json "$dir/ate.json" >/dev/null 2>&1 \
    || { echo "$1: df_eval ate failed"; return 0; }
  summary "$1" "$dir"
}
echo "df_slam offline, $frames frames; per-frame medians in ms (2-core machine, $(nproc) threads)${SET:+; --set '$SET'}"
for preset in $presets; do
  seq="$seqs/${preset}_$frames"
  [ -f "$seq/groundtruth.txt" ] ||
    "$bin/df_make_sequence" --preset "$preset" --frames "$frames" --out "$seq" >/dev/null 2>&1
  for det in $detectors; do run "${preset}_$det" "$seq" "$det"; done
done
if [ -n "$scenes" ] && [ -d "$scenes" ]; then
  for det in $detectors; do
    [ "$det" = simulated ] && det=none  # no ground-truth instances: motion segmentation alone
    run "7scenes_$det" "$scenes" "$det" 7scenes
  done
fi
