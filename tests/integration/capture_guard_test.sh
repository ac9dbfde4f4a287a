#!/usr/bin/env bash
# df_capture stops when asked and refuses to share its namespace: SIGTERM ends a real-time
# wait for a frame stamped a day later, a one-hour linger and a lockstep start wait at once
# (each would otherwise sleep for its full length), exit code 0; a second capture on the same
# namespace refuses to start, naming the first one's host and pid, and the first goes on.
# Over UDP: no RouDi needed.
source "$(dirname "$0")/lib.sh"
"$BIN/df_make_sequence" --preset static_xyz --out "$TMP/seq" --frames 6 --threads 1 >/dev/null 2>&1 \
  || fail "df_make_sequence failed"
# A copy whose fourth frame is stamped a day after the third.
mkdir -p "$TMP/far"
ln -s "$TMP/seq/rgb" "$TMP/far/rgb"; ln -s "$TMP/seq/depth" "$TMP/far/depth"
head -3 "$TMP/seq/associations.txt" >"$TMP/far/associations.txt"
read -r _ rgb _ depth < <(sed -n 4p "$TMP/seq/associations.txt")
echo "86401.000000 $rgb 86401.000000 $depth" >>"$TMP/far/associations.txt"
dds="dds { ns: \"$NS\" transport: \"udp\" }"

# Runs capture with the given flags until its log shows $1, sends SIGTERM, expects exit 0
# within 3 s (the waits it is stopped in last a day, an hour, a minute).
stop_during() {
  local ready="$1" name="$2"; shift 2
  "$BIN/df_capture" "$@" >"$TMP/$name.log" 2>&1 &
  local p=$!; pids+=($p)
  for _ in $(seq 400); do grep -q "$ready" "$TMP/$name.log" && break; sleep 0.05; done
  grep -q "$ready" "$TMP/$name.log" || fail "$name: never logged '$ready': $(tail -3 "$TMP/$name.log")"
  sleep 0.5
  kill -TERM $p
  for _ in $(seq 60); do kill -0 $p 2>/dev/null || break; sleep 0.05; done
  if kill -0 $p 2>/dev/null; then kill -KILL $p; fail "$name: still running 3 s after SIGTERM"; fi
  wait $p || fail "$name: exit code $? after SIGTERM: $(tail -3 "$TMP/$name.log")"
}
stop_during "publishing TUM folder" far_stamp "$TMP/far" --set "$dds"
grep -q "done: 3 frames published" "$TMP/far_stamp.log" || fail "far stamp: $(grep done: "$TMP/far_stamp.log")"
pass "SIGTERM ends the real-time wait for a frame stamped a day later (3 frames published)"
stop_during "publishing TUM folder" linger "$TMP/seq" --set "$dds" --set 'playback: FLAT_OUT' \
  --set 'linger_s: 3600'
grep -q "done: 6 frames published" "$TMP/linger.log" || fail "linger: $(grep done: "$TMP/linger.log")"
pass "SIGTERM ends a linger_s of one hour (after all 6 frames)"
stop_during "lockstep: waiting up to" start_wait "$TMP/seq" --set "$dds" --set 'playback: LOCKSTEP' \
  --set 'lockstep_stages: "nobody"' --set 'start_wait_s: 60'
pass "SIGTERM ends a lockstep start wait of one minute"

# Two captures on one namespace: the second refuses, naming the first.
"$BIN/df_capture" "$TMP/far" --set "$dds" >"$TMP/first.log" 2>&1 &
first=$!; pids+=($first)
for _ in $(seq 400); do grep -q "publishing TUM folder" "$TMP/first.log" && break; sleep 0.05; done
if "$BIN/df_capture" "$TMP/seq" --set "$dds" >"$TMP/second.log" 2>&1; then
  fail "a second capture on $NS started: $(tail -3 "$TMP/second.log")"
fi
grep -q "another writer of $NS/frames is running (df_capture host=$(hostname) pid=$first)" "$TMP/second.log" \
  || fail "the refusal does not name the first capture (pid $first): $(tail -2 "$TMP/second.log")"
grep -q "frames published" "$TMP/second.log" && fail "the refused capture published frames"
kill -0 $first 2>/dev/null || fail "the first capture died: $(tail -3 "$TMP/first.log")"
kill -TERM $first; wait $first || fail "first capture exit code $?"
# Another namespace is fine.
"$BIN/df_capture" "$TMP/seq" --set "dds { ns: \"${NS}_other\" transport: \"udp\" }" --set 'playback: FLAT_OUT' \
  --set 'linger_s: 0' >"$TMP/other.log" 2>&1 || fail "capture on another namespace: $(tail -3 "$TMP/other.log")"
pass "a second capture on $NS refuses to start, naming host $(hostname) pid $first"
