#!/usr/bin/env bash
# A restarted capture goes on after its last frame done (resume_file), in a new run epoch:
# capture in lockstep with df_slam run on a generated sequence; capture SIGKILLed mid-run and
# started again with the same resume file, as the supervisor does. The run finishes with a pose
# for every frame, no stamp twice and no frame played twice from frame 0: the new capture
# publishes only the frames after the last one its record names, and SLAM answers at most one
# frame it tracked already. Then: a record of a run played to its end makes a capture publish
# nothing (exit 0, saying so); a record of another folder is ignored, naming it; a malformed one
# is named with its file and line; both play from frame 0.
# Over UDP with a 1 s participant lease (no RouDi needed).
source "$(dirname "$0")/lib.sh"
N=60
"$BIN/df_make_sequence" --preset static_xyz --out "$TMP/seq" --frames $N --threads 1 >/dev/null 2>&1 \
  || fail "df_make_sequence failed"
XML='<Discovery><LeaseDuration>1s</LeaseDuration></Discovery>'
DDS="dds { ns: \"$NS\" transport: \"udp\" extra_xml: \"$XML\" }"
OUT="$TMP/out"
STATE="$TMP/run/state/capture.resume"
poses() { local n; n=$(grep -vc '^#' "$OUT/trajectory.txt" 2>/dev/null) || true; echo "${n:-0}"; }
wait_exit() {  # pid, what, seconds
  for _ in $(seq $(($3 * 20))); do kill -0 "$1" 2>/dev/null || { wait "$1"; return $?; }; sleep 0.05; done
  fail "$2 still running after $3 s"
}
capture_start() {  # log name, extra --set
  "$BIN/df_capture" "$TMP/seq" --set "$DDS" --set 'playback: LOCKSTEP' --set 'lockstep_stages: "slam"' \
    --set 'start_wait_s: 30' --set 'lockstep_timeout_s: 30' --set "resume_file: \"$STATE\"" \
    >"$TMP/$1.log" 2>&1 &
  cap=$!; pids+=($cap)
}
field() { awk -v k="$1" '$1==k {print $2}' "$STATE"; }

# --- SIGKILL of capture mid-run, started again with the same record ---
"$BIN/df_slam" run --set "$DDS" --set "output { dir: \"$OUT\" log_every: 0 }" \
  --set 'writers_grace_s: 5' >"$TMP/slam.log" 2>&1 &
slam=$!; pids+=($slam)
capture_start capture1
for _ in $(seq 1200); do [ "$(poses)" -ge 25 ] && break; sleep 0.05; done
[ "$(poses)" -ge 25 ] || fail "no 25 poses before the kill: $(tail -3 "$TMP/capture1.log")"
kill -KILL $cap; wait $cap 2>/dev/null || true
at_kill=$(poses)
grep -q "resume file $STATE: none yet, playing from frame 0" "$TMP/capture1.log" \
  || fail "the first capture did not start a record: $(grep -i resume "$TMP/capture1.log")"
done_before=$(field frames_done)
[ "$(field finished)" = 0 ] || fail "record after the kill: $(cat "$STATE")"
# The record trails SLAM by at most the frame that was out when capture was killed.
[ "$done_before" -ge $((at_kill - 1)) ] && [ "$done_before" -le "$at_kill" ] \
  || fail "record says $done_before frames done, SLAM had $at_kill poses"
cp "$OUT/trajectory.txt" "$TMP/before_kill.txt"
capture_start capture2
wait_exit $cap "the restarted capture" 120 || fail "the restarted capture failed: $(tail -5 "$TMP/capture2.log")"
wait_exit $slam "the SLAM service" 60 || fail "SLAM failed: $(tail -5 "$TMP/slam.log")"
grep -q "resume file $STATE: going on after the frame stamped [0-9]* ns (loop 0, $done_before frames done before): frame $done_before of $N is next" \
  "$TMP/capture2.log" || fail "the restarted capture did not resume: $(grep -i resume "$TMP/capture2.log")"
grep -q "done: $((N - done_before)) frames published" "$TMP/capture2.log" \
  || fail "the restarted capture should publish the $((N - done_before)) frames left: $(grep done: "$TMP/capture2.log")"
grep -q "0 lockstep timeouts" "$TMP/capture2.log" || fail "lockstep timeouts: $(grep done: "$TMP/capture2.log")"
again=$(grep -o "([0-9]* frame(s) tracked before it answered skipped)" "$TMP/slam.log" | tr -dc '0-9')
[ "${again:-0}" -le 1 ] || fail "SLAM answered $again frames it had tracked already (a replay)"
[ "$(grep -c "stream ended" "$TMP/slam.log")" -eq 1 ] || fail "the stream ended before the restarted capture's frames"
[ "$(field finished)" = 1 ] && [ "$(field frames_done)" = $N ] || fail "record at the end: $(cat "$STATE")"
/usr/bin/python3 - "$TMP/before_kill.txt" "$OUT/trajectory.txt" "$TMP/seq/groundtruth.txt" <<'PY' || fail "trajectory check"
import sys
def stamps(path):
    return [round(float(l.split()[0]), 4) for l in open(path) if l.strip() and not l.startswith("#")]
before, final, frames = (stamps(p) for p in sys.argv[1:])
assert len(final) == len(set(final)), "a stamp twice in the trajectory"
assert set(before) <= set(final), "a pose written before the kill is lost"
missing = [i for i, s in enumerate(frames) if s not in set(final)]
assert not missing, f"frames {missing[:10]} have no pose"
PY
pass "capture killed after $at_kill poses: the new capture went on at frame $done_before of $N, $N of $N poses, SLAM tracked ${again:-0} frame(s) twice"

# --- a record of a run played to its end: nothing left to publish ---
"$BIN/df_capture" "$TMP/seq" --set "$DDS" --set 'playback: FLAT_OUT' --set "resume_file: \"$STATE\"" \
  --set 'linger_s: 0' >"$TMP/capture3.log" 2>&1 || fail "capture on a finished record: $(tail -3 "$TMP/capture3.log")"
grep -q "the previous run played .* to its end ($N frames); nothing left to publish" "$TMP/capture3.log" \
  || fail "no word of the finished record: $(grep -i resume "$TMP/capture3.log")"
grep -q "done: 0 frames published" "$TMP/capture3.log" || fail "$(grep done: "$TMP/capture3.log")"
pass "a record of a finished run: capture publishes nothing and says why"

# --- a record of another folder, and a malformed one: named, frame 0 ---
sed -i "s|^folder .*|folder /elsewhere|" "$STATE"
"$BIN/df_capture" "$TMP/seq" --set "$DDS" --set 'playback: FLAT_OUT' --set "resume_file: \"$STATE\"" \
  --set 'linger_s: 0' --set 'max_frames: 3' >"$TMP/capture4.log" 2>&1 || fail "capture: $(tail -3 "$TMP/capture4.log")"
grep -q "resume file $STATE ignored (it is for folder /elsewhere, not .*seq); playing from frame 0" \
  "$TMP/capture4.log" || fail "another folder's record: $(grep -i resume "$TMP/capture4.log")"
grep -q "done: 3 frames published" "$TMP/capture4.log" || fail "$(grep done: "$TMP/capture4.log")"
sed -i "s|^last_sensor_ns .*|last_sensor_ns 12abc|" "$STATE"
line=$(grep -n '^last_sensor_ns' "$STATE" | cut -d: -f1)
"$BIN/df_capture" "$TMP/seq" --set "$DDS" --set 'playback: FLAT_OUT' --set "resume_file: \"$STATE\"" \
  --set 'linger_s: 0' --set 'max_frames: 3' >"$TMP/capture5.log" 2>&1 || fail "capture: $(tail -3 "$TMP/capture5.log")"
grep -q "resume file $STATE:$line: last_sensor_ns '12abc' is not an integer in range; playing from frame 0" \
  "$TMP/capture5.log" || fail "a malformed record: $(grep -i resume "$TMP/capture5.log")"
grep -q "done: 3 frames published" "$TMP/capture5.log" || fail "$(grep done: "$TMP/capture5.log")"
pass "another folder's record and a malformed one are named and ignored (frame 0)"
