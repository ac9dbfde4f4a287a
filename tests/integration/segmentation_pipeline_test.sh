#!/usr/bin/env bash
# Geometric segmentation, the SIMULATED detector and the fusion service behind capture (lockstep
# on the fusion stage, shared memory): object_segments answers every frame with classes, with the
# detector reading full frames or the reduced JPEG colour topic (color_small, for a detector on
# another host); with no detector at all, the frames still come, marked as without detections.
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=12
"$BIN/df_make_sequence" --preset default --out "$TMP/seq" --frames 40 --no-models >/dev/null 2>&1 \
  || fail "df_make_sequence failed"
# Frames 20.. show the car, the person and the drum.
mkdir -p "$TMP/cut"
/usr/bin/python3 - "$TMP/seq" "$TMP/cut" $N <<'PY'
import os, shutil, sys
src, dst, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
for name in os.listdir(src):
    p = os.path.join(src, name)
    if os.path.isdir(p): shutil.copytree(p, os.path.join(dst, name))
    else: shutil.copy(p, dst)
lines = [l for l in open(os.path.join(src, "associations.txt")) if not l.startswith("#")]
open(os.path.join(dst, "associations.txt"), "w").writelines(lines[20:20 + n])
PY

# Bad configurations are named, before any DDS traffic.
expect_named() {  # what-to-find, command...
  local want=$1; shift
  if "$@" >"$TMP/bad.out" 2>&1; then fail "accepted: $*"; fi
  grep -q "$want" "$TMP/bad.out" || fail "'$want' not named: $(cat "$TMP/bad.out")"
}
expect_named "persn" "$BIN/df_detector" --set 'class_score_thresholds { key: "persn" value: 0.5 }'
expect_named "nonsense" "$BIN/df_detector" --set 'model: "nonsense"'
expect_named "sim_sequence" "$BIN/df_detector" --set 'model: "simulated"' --set 'sim_sequence: "/nowhere"'
expect_named "input" "$BIN/df_detector" --set 'model: "simulated"' --set "sim_sequence: \"$TMP/seq\"" --set 'input: "depth"'
expect_named "karr" "$BIN/df_fusion" --set 'classes { rigid: "karr" }'
pass "bad detector and fusion configurations are named"

run_pipeline() {  # name, with_detector, [detector input: frames | color_small]
  local name=$1 input=${3:-frames}
  "$BIN/df_tap" echo "$NS/object_segments" -n $N --items 3 >"$TMP/$name.echo" 2>"$TMP/$name.echo.err" &
  local echo_pid=$!; pids+=($echo_pid)
  "$BIN/df_geoseg" --set "dds { ns: \"$NS\" }" >"$TMP/$name.geoseg.log" 2>&1 &
  local g=$!; pids+=($g)
  local d=""
  if [ "$2" = yes ]; then
    "$BIN/df_detector" --set "dds { ns: \"$NS\" }" --set 'model: "simulated"' \
      --set "sim_sequence: \"$TMP/cut\"" --set "input: \"$input\"" >"$TMP/$name.detector.log" 2>&1 &
    d=$!; pids+=($d)
  fi
  "$BIN/df_fusion" --set "dds { ns: \"$NS\" }" >"$TMP/$name.fusion.log" 2>&1 &
  local f=$!; pids+=($f)
  "$BIN/df_capture" "$TMP/cut" --set "dds { ns: \"$NS\" }" --set 'playback: LOCKSTEP' \
    --set 'lockstep_stages: "fusion"' --set 'start_wait_s: 20' --set 'color_small_width: 320' \
    >"$TMP/$name.capture.log" 2>&1 \
    || fail "$name: capture failed: $(tail "$TMP/$name.capture.log")"
  grep -q "0 lockstep timeouts" "$TMP/$name.capture.log" || fail "$name: lockstep timeouts: $(grep done: "$TMP/$name.capture.log")"
  wait $g || fail "$name: geoseg failed: $(tail -3 "$TMP/$name.geoseg.log")"
  [ -n "$d" ] && { wait $d || fail "$name: detector failed: $(tail -3 "$TMP/$name.detector.log")"; }
  wait $f || fail "$name: fusion failed: $(tail -3 "$TMP/$name.fusion.log")"
  wait $echo_pid || fail "$name: echo failed: $(cat "$TMP/$name.echo.err")"
}

check() {  # name, expect_detections (yes/no)
  /usr/bin/python3 - "$TMP/$1.echo" $N "$2" <<'PY'
import re, sys
text, n, want = open(sys.argv[1]).read(), int(sys.argv[2]), sys.argv[3] == "yes"
msgs = text.split("header:")[1:]
assert len(msgs) == n, f"{len(msgs)} messages"
seqs = sorted(int(re.search(r"\bseq:\s*(\d+)", m).group(1)) for m in msgs)
assert seqs == list(range(n)), seqs
used = [re.search(r"detections_used:\s*(\w+)", m).group(1) for m in msgs]
counts = [int(re.search(r"instance_count:\s*(\d+)", m).group(1)) for m in msgs]
classes = set(int(c) for c in re.findall(r"class_id:\s*(-?\d+)", text))
if want:
    assert used.count("true") >= n - 1, used
    assert sum(c > 0 for c in counts) >= n // 2, counts
    assert 2 in classes or 0 in classes, classes   # car or person
else:
    assert all(u == "false" for u in used), used
    assert all(c == 0 for c in counts), counts
print(f"ok: {n} frames, detections used {used.count('true')}, instances per frame {counts}, classes {sorted(classes)}")
PY
}
run_pipeline full yes
check full yes || fail "object_segments with the detector: $(head -c 1500 "$TMP/full.echo")"
pass "object_segments for every frame with classes (simulated detector)"
run_pipeline small yes color_small
check small yes || fail "object_segments with the detector on color_small: $(head -c 1500 "$TMP/small.echo")"
grep -q "waiting for frames on $NS/color_small" "$TMP/small.detector.log" || fail "detector input: $(head -3 "$TMP/small.detector.log")"
pass "the detector on the reduced JPEG colour topic (for a second host): boxes land on the full frame"
run_pipeline nodet no
check nodet no || fail "object_segments without a detector: $(head -c 1500 "$TMP/nodet.echo")"
grep -q "0 with their own detections" "$TMP/nodet.fusion.log" || fail "fusion: $(tail -2 "$TMP/nodet.fusion.log")"
pass "without a detector every frame still comes, marked as published without detections"
