#!/usr/bin/env bash
# Real-data benchmark (docs/dynamics.md, "Real frames"): df_slam offline on every real RGB-D
# folder given, with dynamics on (the defaults: YOLOv5s, motion segmentation, object maps), off
# (the static core alone) and, where the folder has ground-truth masks of its mover (masks/),
# with those masks. Prints one table: ATE RMSE, lost frames, the mean fraction of pixels left out
# of tracking, the mean fraction motion segmentation flagged as moving, the mover's mask IoU
# (the run's invalid mask against masks/, df_eval mask), median ms per frame of the whole SLAM
# step and of the object stages, and the guards' counts.
# usage: tests/bench/run_real_bench.sh [FOLDER...]
#   default folders: ../shared/data/7scenes-300 ../shared/data/7scenes-dyn-300
# environment: PRESET (intrinsics preset for a folder without intrinsics.txt; default 7scenes),
#   MODES (default "on off masks"), SET (extra --set for every run), TAG (out/bench/real/TAG),
#   BIN (the binaries; default build/bin).
# Needs a build (bash deploy/build.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${BIN:-$root/build/bin}"
out="$root/out/bench/real/${TAG:-default}"
modes="${MODES:-on off masks}"
folders=("$@")
[ ${#folders[@]} -eq 0 ] && folders=("$root/../shared/data/7scenes-300" "$root/../shared/data/7scenes-dyn-300")
mkdir -p "$out"
set_args=()
[ -n "${SET:-}" ] && set_args=(--set "$SET")

row() {  # name mode dir folder
  /usr/bin/python3 - "$@" <<'PY'
import json, os, sys
name, mode, d, folder = sys.argv[1:5]
s = json.load(open(f"{d}/summary.json"))
rmse = json.load(open(f"{d}/ate.json"))["ate"]["translation_m"]["rmse"]
st = s["stages_ms"]
med = lambda k: st[k]["median"] if k in st else 0.0
iou = "   -  "
if os.path.exists(f"{d}/mask.json"):
    iou = f"{json.load(open(f'{d}/mask.json'))['mask']['mean_iou']:6.3f}"
g = s.get("guards", {})
left = s.get("left_out_fraction", {}).get("mean", 0.0)
print(f"{name:22s} {mode:6s} {rmse*100:7.2f} {s['lost']:4d}/{s['frames']:<4d} {100*left:8.2f} "
      f"{100*s['motion_fraction']['mean']:8.3f} {iou} {med('total'):7.1f} {med('objects'):7.1f} "
      f"{g.get('frames_guarded', 0):6d} {g.get('rebuilds', 0):3d}", flush=True)
PY
}

printf "%-22s %-6s %7s %9s %8s %8s %6s %7s %7s %6s %3s\n" sequence mode "ATE cm" lost "left %" \
  "moving %" IoU "ms" "obj ms" guard reb
for folder in "${folders[@]}"; do
  name="$(basename "$folder")"
  [ -f "$folder/associations.txt" ] || { echo "$name: no associations.txt in $folder, skipped"; continue; }
  for mode in $modes; do
    args=()
    case "$mode" in
      on) ;;
      off) args=(--dynamics off) ;;
      masks)
        [ -d "$folder/masks" ] || continue
        args=(--masks "$folder/masks") ;;
      *) echo "unknown mode $mode" >&2; exit 2 ;;
    esac
    dir="$out/$name-$mode"
    rm -rf "$dir"
    preset=()
    [ -f "$folder/intrinsics.txt" ] || preset=(--preset "${PRESET:-7scenes}")
    if ! "$bin/df_slam" offline "$folder" -o "$dir" "${preset[@]}" "${args[@]}" \
        --set 'output { log_every: 0 }' "${set_args[@]}" >"$dir.out" 2>"$dir.log"; then
      echo "$name $mode: df_slam failed, see $dir.log"; tail -3 "$dir.log"; continue
    fi
    "$bin/df_eval" ate "$folder/groundtruth.txt" "$dir/trajectory.txt" --json "$dir/ate.json" \
      >/dev/null 2>&1 || { echo "$name $mode: df_eval ate failed"; continue; }
    if [ -d "$folder/masks" ] && [ "$mode" != off ]; then
      "$bin/df_eval" mask "$folder/masks" "$dir/invalid" --json "$dir/mask.json" >/dev/null \
        || echo "$name $mode: df_eval mask failed"
    fi
    row "$name" "$mode" "$dir" "$folder"
  done
done
echo "(left %: pixels left out of the static map's tracking; moving %: of the pixels motion"
echo " segmentation looked at, those it flagged; IoU: the invalid mask against masks/, mean over"
echo " frames with a mover; ms: median SLAM step; obj ms: median object stages; guard: frames"
echo " tracked with only persons left out; reb: static map rebuilds. Outputs in $out)"
