#!/usr/bin/env bash
# df_slam as a user runs it: offline over a generated folder (files written, ATE printed and
# small, PLY readable), bad input and bad configuration named, then as the DDS service behind
# capture in lockstep: every frame answered on camera_pose, and the service's trajectory equal
# to the offline one (same library, same frames, deterministic).
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=30
"$BIN/df_make_sequence" --preset static_xyz --out "$TMP/seq" --frames $N >/dev/null 2>&1 \
  || fail "df_make_sequence failed"

# --- offline ---
"$BIN/df_slam" offline "$TMP/seq" -o "$TMP/off" >"$TMP/off.out" 2>"$TMP/off.err" \
  || fail "offline failed: $(tail -5 "$TMP/off.err")"
for f in trajectory.txt map.ply timings.log summary.json; do
  [ -s "$TMP/off/$f" ] || fail "offline wrote no $f"
done
[ "$(grep -vc '^#' "$TMP/off/trajectory.txt")" -eq $N ] || fail "trajectory: $(wc -l < "$TMP/off/trajectory.txt") lines"
[ "$(grep -c '^timing seq=' "$TMP/off/timings.log")" -eq $N ] || fail "timings.log lines"
ate_cm=$(sed -n 's/^ATE RMSE \([0-9.]*\) cm.*/\1/p' "$TMP/off.out")
[ -n "$ate_cm" ] || fail "no ATE printed: $(cat "$TMP/off.out")"
awk -v a="$ate_cm" 'BEGIN { exit !(a < 1.0) }' || fail "offline ATE $ate_cm cm >= 1 cm"
pass "offline: $N poses, ATE $ate_cm cm"
/usr/bin/python3 - "$TMP/off/summary.json" $N <<'PY' || fail "summary.json: $(cat "$TMP/off/summary.json")"
import json, sys
s, n = json.load(open(sys.argv[1])), int(sys.argv[2])
st = s["stages_ms"]
for k in ("tracking", "stage1", "motion", "stage2"):  # every frame after the first
    assert st[k]["count"] == n - 1, f"{k}: {st[k]['count']} frames timed, not {n - 1}"
for k in ("fusion", "prediction"):  # every frame fused, the first included
    assert st[k]["count"] == n, f"{k}: {st[k]['count']} frames timed, not {n}"
# A static scene: motion segmentation flags next to nothing (issue 11: <= 1 % on average).
m = s["motion_fraction"]
assert m["frames"] == n - 1 and 0 <= m["mean"] <= 0.01 and m["max"] <= 1, m
print(f"ok: summary.json: stage parts timed; {100 * m['mean']:.3f} % of pixels flagged moving on a static scene")
PY
/usr/bin/python3 - "$TMP/off/map.ply" <<'PY' || exit 1
import struct, sys
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
header = data[:end].decode().splitlines()
assert header[0] == "ply" and header[1] == "format binary_little_endian 1.0", header[:2]
count = int(next(l.split()[2] for l in header if l.startswith("element vertex")))
props = [l.split() for l in header if l.startswith("property")]
names = [p[-1] for p in props]
for n in ("x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "radius", "confidence"):
    assert n in names, f"no {n} in {names}"
size = {"float": 4, "uchar": 1, "double": 8}
stride = sum(size[p[1]] for p in props)
assert len(data) - end == count * stride, (len(data) - end, count, stride)
assert count > 10000, f"only {count} surfels"
print(f"ok: map.ply {count} surfels, binary, fields {' '.join(names)}")
PY

# --- bad input and configuration ---
if "$BIN/df_slam" offline "$TMP/nowhere" -o "$TMP/bad" >"$TMP/bad.out" 2>&1; then fail "missing folder accepted"; fi
grep -q "nowhere" "$TMP/bad.out" || fail "missing folder not named: $(cat "$TMP/bad.out")"
if "$BIN/df_slam" offline "$TMP/seq" -o "$TMP/bad" --set 'slam { tracking { icp_weight: "ten" } }' >"$TMP/bad.out" 2>&1; then
  fail "bad config accepted"
fi
grep -q "icp_weight" "$TMP/bad.out" || fail "bad config not named: $(cat "$TMP/bad.out")"
if "$BIN/df_slam" offline "$TMP/seq" -o "$TMP/bad" --set 'slam { system { processing_downscale: 3 } }' >"$TMP/bad.out" 2>&1; then
  fail "bad value accepted"
fi
grep -q "processing_downscale" "$TMP/bad.out" || fail "bad value not named: $(cat "$TMP/bad.out")"
pass "bad folder and bad configuration named"

# --- masks: a generated sequence's instances/ (ground-truth segmentation) ---
"$BIN/df_make_sequence" --preset default --out "$TMP/dyn" --frames 8 --no-models >/dev/null 2>&1 \
  || fail "df_make_sequence default failed"
"$BIN/df_slam" offline "$TMP/dyn" -o "$TMP/dyn_out" --masks "$TMP/dyn/instances" >"$TMP/dyn.out" 2>"$TMP/dyn.err" \
  || fail "masked offline failed: $(tail -5 "$TMP/dyn.err")"
grep -q "^processed 8 frames (0 lost, 0 bad)" "$TMP/dyn.out" || fail "masked run: $(cat "$TMP/dyn.out")"
# instances.json beside the masks gives them their classes and kinds: the car (rigid) gets an
# object map of its own; the person and the drum do not.
grep -q "classes and kinds of 3 instances" "$TMP/dyn.err" || fail "instances.json not read: $(grep masks "$TMP/dyn.err")"
grep -q '"class_name": "car"' "$TMP/dyn_out/objects.json" \
  || fail "no object map for the car from ground-truth masks: $(cat "$TMP/dyn_out/objects.json")"
if grep -q '"class_name": "person"\|"class_name": "unknown"' "$TMP/dyn_out/objects.json"; then
  fail "an object map for a non-rigid or unknown instance: $(cat "$TMP/dyn_out/objects.json")"
fi
mkdir -p "$TMP/few_masks"
cp "$TMP/dyn/instances/1.000000.png" "$TMP/few_masks/"
"$BIN/df_slam" offline "$TMP/dyn" -o "$TMP/few_out" --masks "$TMP/few_masks" --max-frames 3 >"$TMP/few.out" 2>&1 || true
grep -q "no mask $TMP/few_masks/1.033333.png" "$TMP/few.out" || fail "missing mask not named: $(cat "$TMP/few.out")"
grep -q "^processed 1 frames (0 lost, 2 bad)" "$TMP/few.out" || fail "missing masks not counted as bad frames: $(cat "$TMP/few.out")"
pass "masks: instances/ applied with instances.json's classes (the car mapped); a missing mask file is named and its frame skipped"

# --- the service behind capture (lockstep, shared memory) ---
"$BIN/df_tap" record -o "$TMP/poses.mcap" "$NS/camera_pose" --wait 20 --idle 4 >"$TMP/rec.out" 2>"$TMP/rec.err" &
rec=$!; pids+=($rec)
"$BIN/df_slam" run --set "dds { ns: \"$NS\" }" --set "output { dir: \"$TMP/svc\" }" \
  >"$TMP/slam.log" 2>&1 &
slam=$!; pids+=($slam)
"$BIN/df_capture" "$TMP/seq" --set "dds { ns: \"$NS\" }" --set 'playback: LOCKSTEP' \
  --set 'lockstep_stages: "slam"' --set 'start_wait_s: 20' >"$TMP/capture.log" 2>&1 \
  || fail "capture failed: $(tail "$TMP/capture.log")"
grep -q "0 lockstep timeouts" "$TMP/capture.log" || fail "lockstep timeouts: $(grep done: "$TMP/capture.log")"
wait $slam || fail "slam service failed: $(tail "$TMP/slam.log")"
grep -q "stream ended (the frame writers left)" "$TMP/slam.log" || fail "no end of stream: $(tail "$TMP/slam.log")"
wait $rec || fail "pose recorder failed: $(cat "$TMP/rec.err")"
grep -q "$N msgs" "$TMP/rec.out" || fail "camera_pose: $(cat "$TMP/rec.out")"
[ "$(grep -vc '^#' "$TMP/svc/trajectory.txt")" -eq $N ] || fail "service trajectory: $(wc -l < "$TMP/svc/trajectory.txt") lines"
"$BIN/df_eval" ate "$TMP/seq/groundtruth.txt" "$TMP/svc/trajectory.txt" --json "$TMP/svc_ate.json" >/dev/null \
  || fail "df_eval ate on the service trajectory failed"
svc_cm=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['ate']['translation_m']['rmse']*100)" "$TMP/svc_ate.json")
awk -v a="$svc_cm" 'BEGIN { exit !(a < 1.0) }' || fail "service ATE $svc_cm cm >= 1 cm"
pass "service: $N frames answered on camera_pose in lockstep; $N poses, ATE $svc_cm cm"
