#!/usr/bin/env bash
# Every bad option is refused at start by the real binaries: exit status not 0, and one error
# line naming the field and its allowed range (or the file and line), before any DDS
# participant is made (no RouDi needed; a service that got past validation would wait for
# frames and hit the timeout instead).
source "$(dirname "$0")/lib.sh"
udp="dds { transport: \"udp\" ns: \"$NS\" }"

# expect_refused <expected text> <binary> <args...>
n=0
expect_refused() {
  local want="$1"; shift
  local log="$TMP/case$n.log"; n=$((n + 1))
  local rc=0
  timeout 30 "$@" >"$log" 2>&1 || rc=$?
  [ "$rc" -ne 124 ] || fail "$* ran on (timeout) instead of refusing: $(tail -3 "$log")"
  [ "$rc" -ne 0 ] || fail "$* exited 0; expected a refusal naming: $want"
  grep -qF -- "$want" "$log" || fail "$* exited $rc without '$want': $(tail -3 "$log")"
  pass "refused ($want)"
}

# SLAM: df_slam run and offline read the same options.
slam_bad=(
  "slam { map { confidence_sigma: 0 } }|slam.map.confidence_sigma is 0, allowed: > 0 and <= 100"
  "slam { map { unstable_max_unseen_frames: -1 } }|slam.map.unstable_max_unseen_frames is -1, allowed: >= 0"
  "slam { prediction { threads: -4 } }|slam.prediction.threads is -4, allowed: >= 0 and <= 256"
  "slam { prediction { max_splat_radius_px: inf } }|slam.prediction.max_splat_radius_px is inf, allowed: >= 0 and <= 64 (unit: px)"
  "slam { tracking { icp_max_distance_m: nan } }|slam.tracking.icp_max_distance_m is nan, allowed: > 0 and <= 1 (unit: m)"
  "slam { system { processing_downscale: 3 } }|slam.system.processing_downscale is 3, allowed: >= 1 and <= 2"
  "idle_exit_s: -1|idle_exit_s is -1, allowed: >= 0"
  "stage: \"\"|stage is empty, allowed: not empty"
  "geoseg { min_segment_pixels: 0 }|geoseg.min_segment_pixels is 0, allowed: >= 1 and <= 307200"
  "instances { min_iou: 2 }|instances.min_iou is 2, allowed: > 0 and <= 1"
  "classes { rigid: \"cup\" non_rigid: \"cup\" }|class 'cup' is listed in both classes.rigid and classes.non_rigid"
  "classes { rigid: \"\" }|classes.rigid[0] is empty"
)
for c in "${slam_bad[@]}"; do
  expect_refused "${c#*|}" "$BIN/df_slam" run --set "$udp" --set "${c%%|*}"
done
expect_refused "slam.map.confidence_sigma is 0" \
  "$BIN/df_slam" offline "$TMP/none" -o "$TMP/out" --set 'slam { map { confidence_sigma: 0 } }'
expect_refused "configuration file '$TMP' is not a regular file" "$BIN/df_slam" run --config "$TMP"
expect_refused "configuration file '$TMP/none.pbtxt' does not exist" \
  "$BIN/df_slam" run --config "$TMP/none.pbtxt"

# A nonsensical intrinsics.txt: refused naming the file, line, field and range.
mkdir -p "$TMP/k1" "$TMP/k2" "$TMP/k3"
echo "1e-300 535 320 240 640 480 5000" >"$TMP/k1/intrinsics.txt"
echo "535 539 1e300 240 640 480 5000" >"$TMP/k2/intrinsics.txt"
printf '# fx fy cx cy w h units\n535 539 320 240 64000 480 5000\n' >"$TMP/k3/intrinsics.txt"
expect_refused "$TMP/k1/intrinsics.txt:1: fx is 1e-300, allowed [32, 12800] for 640x480 images" \
  "$BIN/df_slam" offline "$TMP/k1" -o "$TMP/out"
expect_refused "$TMP/k2/intrinsics.txt:1: cx is 1e+300, allowed [0, 640]" \
  "$BIN/df_slam" offline "$TMP/k2" -o "$TMP/out"
expect_refused "$TMP/k3/intrinsics.txt:2: image size 64000x480, allowed: 1x1 to 640x480" \
  "$BIN/df_slam" offline "$TMP/k3" -o "$TMP/out"

# df_slam params shows each range and unit, derived from slam.proto.
"$BIN/df_slam" params >"$TMP/params.txt"
grep -qE '^map.confidence_sigma +0.6 +> 0 and <= 100 ' "$TMP/params.txt" \
  || fail "df_slam params lacks the range of map.confidence_sigma: $(grep confidence_sigma "$TMP/params.txt")"
grep -qE '^prediction.max_splat_radius_px +1 +>= 0 and <= 64 \[px\]' "$TMP/params.txt" \
  || fail "df_slam params lacks the range and unit of max_splat_radius_px"
pass "df_slam params shows ranges and units"

# Capture.
capture_bad=(
  "rate: 0|rate is 0, allowed: > 0 and <= 1000 (unit: x)"
  "rate: -5|rate is -5, allowed: > 0 and <= 1000 (unit: x)"
  "rate: nan|rate is nan, allowed: > 0 and <= 1000 (unit: x)"
  "fx: -535|fx is -535, allowed: > 0 and <= 100000 (unit: px)"
  "fx: nan|fx is nan, allowed: > 0"
  "color_small_jpeg_quality: 1000|color_small_jpeg_quality is 1000, allowed: >= 1 and <= 100"
  "intrinsics_preset: \"fr9\"|intrinsics_preset is \"fr9\", allowed: one of fr1|fr2|fr3|7scenes"
  "lockstep_timeout_s: 0|lockstep_timeout_s is 0, allowed: > 0"
  "linger_s: 1e9|linger_s is 1000000000, allowed: >= 0 and <= 3600 (unit: s)"
  "dds { domain_id: 1000 }|dds.domain_id is 1000, allowed: <= 232"
)
for c in "${capture_bad[@]}"; do
  expect_refused "${c#*|}" "$BIN/df_capture" "$TMP/none" --set "$udp" --set "${c%%|*}"
done

# Detector (model "simulated": no model files needed to get to the check).
detector_bad=(
  "score_threshold: -1|score_threshold is -1, allowed: >= 0 and <= 1"
  "score_threshold: nan|score_threshold is nan, allowed: >= 0 and <= 1"
  "score_threshold: 2|score_threshold is 2, allowed: >= 0 and <= 1"
  "nms_iou_threshold: 2|nms_iou_threshold is 2, allowed: >= 0 and <= 1"
  "dds { ns: \"\" }|dds.ns is empty, allowed: not empty"
  "input_width: 100000|input_width is 100000, allowed: >= 32 and <= 2048 (unit: px)"
  "threads: -1|threads is -1, allowed: >= 0 and <= 256"
  "class_score_thresholds { key: \"person\" value: 1.5 }|class_score_thresholds[person] is 1.5, allowed: >= 0 and <= 1"
)
for c in "${detector_bad[@]}"; do
  expect_refused "${c#*|}" "$BIN/df_detector" --set "$udp" --set "${c%%|*}"
done

# Fusion.
expect_refused "class 'cup' is listed in both classes.rigid and classes.non_rigid" \
  "$BIN/df_fusion" --set "$udp" --set 'classes { rigid: "cup" non_rigid: "cup" }'
expect_refused "detection_deadline_ms is nan, allowed: >= 0 and <= 600000 (unit: ms)" \
  "$BIN/df_fusion" --set "$udp" --set 'detection_deadline_ms: nan'
expect_refused "instances.min_iou is 2, allowed: > 0 and <= 1" "$BIN/df_fusion" --set "$udp" --set 'instances { min_iou: 2 }'

# Geometric segmentation.
expect_refused "params.max_distance_m is -1, allowed: > 0 and <= 1 (unit: m)" \
  "$BIN/df_geoseg" --set "$udp" --set 'params { max_distance_m: -1 }'
expect_refused "params.neighbours is 6, allowed: 4 or 8" \
  "$BIN/df_geoseg" --set "$udp" --set 'params { neighbours: 6 }'

# Every service's --help shows the ranges.
for b in df_capture:"rate .* > 0 and <= 1000 \[x\]" df_detector:"score_threshold .* >= 0 and <= 1" \
         df_fusion:"detection_deadline_ms .* \[ms\]" df_geoseg:"params.neighbours .* >= 4 and <= 8"; do
  "$BIN/${b%%:*}" --help >"$TMP/help.txt" 2>&1 || true
  grep -qE -- "${b#*:}" "$TMP/help.txt" || fail "${b%%:*} --help lacks '${b#*:}'"
done
pass "--help of capture, detector, fusion, geoseg shows ranges"
echo "PASS: $n bad options refused"
