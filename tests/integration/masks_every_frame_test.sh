#!/usr/bin/env bash
# Masks for every frame from detections at a lower rate (issue 13): the whole segmentation
# pipeline behind capture (lockstep on slam, shared memory) with the SIMULATED detector answering
# only every 4th frame (every_nth: 4; the others are answered skipped). The fusion service
# publishes every frame, with the last boxes where they are recent enough; SLAM carries the
# last frame's instances forward over every frame without its own detections. Every frame must
# come with person instances, three in four of them carried forward with their age, and the
# trajectory stays near the ground truth.
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=40
"$BIN/df_make_sequence" --preset walking_xyz --out "$TMP/seq" --frames $N --no-models >/dev/null 2>&1 \
  || fail "df_make_sequence failed"
out="$TMP/slam"
pids=()
# What SLAM left out, with each instance's age (df_tap echo prints "age: N" per instance).
"$BIN/df_tap" echo "$NS/invalid_mask" -n $N --items 0 --idle 30 >"$TMP/invalid.echo" \
  2>"$TMP/invalid.echo.err" &
e=$!
"$BIN/df_geoseg" --set "dds { ns: \"$NS\" }" >"$TMP/geoseg.log" 2>&1 & pids+=($!)
"$BIN/df_detector" --set "dds { ns: \"$NS\" }" --set 'model: "simulated"' --set 'every_nth: 4' \
  --set "sim_sequence: \"$TMP/seq\"" >"$TMP/detector.log" 2>&1 & pids+=($!)
"$BIN/df_fusion" --set "dds { ns: \"$NS\" }" --set 'detection_deadline_ms: 2000' \
  >"$TMP/fusion.log" 2>&1 & pids+=($!)
"$BIN/df_slam" run --set "dds { ns: \"$NS\" }" --set "output { dir: \"$out\" log_every: 1 }" \
  --set 'segments_deadline_ms: 3000' >"$TMP/slam.log" 2>&1 &
s=$!; pids+=($s)
"$BIN/df_capture" "$TMP/seq" --set "dds { ns: \"$NS\" }" --set 'playback: LOCKSTEP' \
  --set 'lockstep_stages: "slam"' --set 'start_wait_s: 30' --set 'lockstep_timeout_s: 60' \
  >"$TMP/capture.log" 2>&1 &
c=$!; pids+=($c)
wait $c || fail "capture failed: $(tail -3 "$TMP/capture.log")"
wait $s || fail "slam failed: $(tail -5 "$TMP/slam.log")"
wait $e || fail "invalid_mask echo failed: $(cat "$TMP/invalid.echo.err")"
kill "${pids[@]}" 2>/dev/null || true

poses=$(grep -vc '^#' "$out/trajectory.txt")
[ "$poses" -eq $N ] || fail "$poses of $N poses"
frames=$(grep -c " instances=" "$TMP/slam.log" || true)
[ "$frames" -eq $N ] || fail "$frames frame log lines for $N frames"
without=$(grep -E "seq=[0-9]+ " "$TMP/slam.log" | grep -c " instances=0 " || true)
own=$(grep -c " detections_age=0 " "$TMP/slam.log" || true)
carried=$(grep -Ec " carried=[1-9]" "$TMP/slam.log" || true)
echo "frame lines $frames, without instances $without, own detections $own, carried $carried"
# The first frame has its own detections (seq 0); a person is in view in every frame.
[ "$without" -le 1 ] || fail "$without frames without instances: $(grep ' instances=0 ' "$TMP/slam.log" | head -3)"
[ "$own" -ge $((N / 4 - 1)) ] && [ "$own" -le $((N / 4 + 1)) ] \
  || fail "$own frames with their own detections (every 4th of $N expected)"
[ "$carried" -ge $((N - N / 4 - 2)) ] || fail "only $carried of $((N - N / 4)) frames got instances carried"
# Ages: 1, 2 or 3 frames (never older than the last detection).
bad=$(grep -E " carried=[1-9]" "$TMP/slam.log" | grep -Evc " detections_age=(-1|[1-3]) " || true)
[ "$bad" -eq 0 ] || fail "$bad carried frames with an unexpected age"
# The topic carries the ages too: the persons of frames with their own detections at age 0, the
# carried ones at 1-3, none older.
/usr/bin/python3 - "$TMP/invalid.echo" $N <<'PY' || fail "invalid_mask ages: $(grep -m5 NON_RIGID "$TMP/invalid.echo")"
import re, sys
ages = [int(a) for a in re.findall(r"kind: NON_RIGID[^}]*age: (\d+)", open(sys.argv[1]).read())]
n = int(sys.argv[2])
print("invalid_mask person ages:", {a: ages.count(a) for a in sorted(set(ages))})
assert ages, "no person instance on invalid_mask"
assert max(ages) <= 3, max(ages)
assert ages.count(0) >= 1 and sum(1 for a in ages if a >= 1) >= n // 4, ages
PY
/usr/bin/python3 - "$out/summary.json" $N <<'PY' || fail "summary.json: $(cat "$out/summary.json" | head -40)"
import json, sys
m = json.load(open(sys.argv[1]))["masks"]
n = int(sys.argv[2])
assert m["own_detections"] + m["reused_detections"] + m["no_detections"] == n, m
assert m["carried"] >= n - n // 4 - 2, m
assert 1 <= m["oldest_carried_frames"] <= 3, m
PY
"$BIN/df_eval" ate "$TMP/seq/groundtruth.txt" "$out/trajectory.txt" --json "$TMP/ate.json" \
  >/dev/null 2>&1 || fail "df_eval ate failed"
rmse=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['ate']['translation_m']['rmse'])" "$TMP/ate.json")
/usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 0.02 else 1)" "$rmse" \
  || fail "ATE $rmse m >= 0.02 m"
pass "detector on every 4th frame: $own own, $carried carried forward, every frame with instances; ATE $rmse m"
