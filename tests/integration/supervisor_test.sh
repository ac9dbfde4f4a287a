#!/usr/bin/env bash
# Capture under the supervisor: RouDi starts first; tap hz shows the sequence's 30 Hz; tap list
# and echo see the topic (echo with capture's run epoch); a killed capture is restarted, with a
# later epoch; down stops the services, RouDi last.
source "$(dirname "$0")/lib.sh"
need_own_roudi
make_sequence 30
{ echo 'name: "supervisor-test"'; capture_service; } > "$TMP/pipeline.pbtxt"
started_ns=$(date +%s%N)
sup_up "$TMP/pipeline.pbtxt"
log="$RUN/supervisord.log"
grep -n "spawned: 'roudi'" "$log" >/dev/null || fail "RouDi was not started"
[ "$(grep -n "spawned:" "$log" | head -1 | grep -c roudi)" = 1 ] || fail "RouDi was not started first"
pass "RouDi started first"

hz=$(timeout 60 "$BIN/df_tap" hz "$NS/frames" --duration 4 2>"$TMP/hz.err" | grep "average rate" | tail -1 | awk '{print $3}') || true
[ -n "$hz" ] || fail "tap hz printed no rate: $(cat "$TMP/hz.err")"
awk -v r="$hz" 'BEGIN { exit !(r > 25 && r < 35) }' || fail "tap hz shows $hz Hz, expected the sequence's 30 Hz"
pass "tap hz shows $hz Hz"

timeout 60 "$BIN/df_tap" list --wait 2 2>"$TMP/list.err" > "$TMP/list.txt" || fail "tap list: $(tail -5 "$TMP/list.err")"
entry=$(grep -A3 "^$NS/frames" "$TMP/list.txt" || true)
[[ "$entry" == *"type: df::msg::RgbdFrame"* ]] || fail "tap list: $(cat "$TMP/list.txt")"
[[ "$entry" == *"df_capture"* ]] || fail "tap list names no capture writer: $entry"
pass "tap list shows $NS/frames with its writer"

timeout 60 "$BIN/df_tap" echo "$NS/frames" -n 1 2>"$TMP/echo.err" > "$TMP/echo.txt" || fail "tap echo: $(tail -5 "$TMP/echo.err")"
grep -q "^width: 640" "$TMP/echo.txt" && grep -q "^  seq: " "$TMP/echo.txt" || fail "tap echo: $(head -20 "$TMP/echo.txt")"
# The run epoch capture set: a wall-clock time in ns after the pipeline came up.
epoch_of() { sed -n 's/^  epoch: \([0-9]*\)$/\1/p' "$1" | head -1; }
epoch=$(epoch_of "$TMP/echo.txt")
[ -n "$epoch" ] || fail "tap echo prints no epoch: $(head -10 "$TMP/echo.txt")"
/usr/bin/python3 -c "import sys; sys.exit(not ($started_ns <= int(sys.argv[1]) <= $(date +%s%N)))" "$epoch" \
  || fail "epoch $epoch is not capture's start (pipeline up at $started_ns ns)"
pass "tap echo prints a frame header with the run epoch $epoch"

sup_kill_restarted capture
grep -q "exited: capture (terminated by SIGKILL; not expected)" "$log" || fail "no crash in supervisord log"
pass "capture killed (pid $killed_pid) and restarted (pid $new_pid)"
# A SIGKILLed capture can leave RouDi stuck, and the watcher then heals (a new RouDi): a tap
# started during the heal cannot register with RouDi (seen in CI). Wait until no heal is under
# way and RouDi's probe answers; a heal that starts just as the tap does gets a second try.
settled() {
  local begun done
  begun=$(grep -c " because " "$RUN/heal.log" 2>/dev/null) || true
  done=$(grep -cE "; started|: FAILED" "$RUN/heal.log" 2>/dev/null) || true
  [ "${begun:-0}" = "${done:-0}" ] && $SUP status | grep -Eq "^roudi .*health: ok"
}
for try in 1 2; do
  for _ in $(seq 600); do settled && break; sleep 0.1; done
  rc=0
  after=$(timeout 60 "$BIN/df_tap" hz "$NS/frames" --wait 15 --duration 2 2>"$TMP/hz2.err") || rc=$?
  [ "$rc" -eq 0 ] && break
done
[ "$rc" -eq 0 ] || fail "tap hz after the restart exited with $rc: $(tail -5 "$TMP/hz2.err"); heals: $(cat "$RUN/heal.log" 2>/dev/null)"
[[ "$after" == *"average rate"* ]] || fail "no frames after restart: $after"
pass "frames flow again after the restart"
# The restarted capture is a new run: tap echo shows a later epoch than before the kill.
timeout 60 "$BIN/df_tap" echo "$NS/frames" -n 1 2>"$TMP/echo2.err" > "$TMP/echo2.txt" || fail "tap echo: $(tail -5 "$TMP/echo2.err")"
epoch2=$(epoch_of "$TMP/echo2.txt")
[ -n "$epoch2" ] && /usr/bin/python3 -c "import sys; sys.exit(not int(sys.argv[2]) > int(sys.argv[1]))" "$epoch" "$epoch2" \
  || fail "epoch after the restart '$epoch2' is not later than $epoch: $(head -10 "$TMP/echo2.txt")"
pass "tap echo shows the restarted capture's new epoch $epoch2"

st=$($SUP status)
grep -q "^health .*RUNNING" <<<"$st" && grep -q "^watch .*RUNNING" <<<"$st" \
  || fail "no health probe or watcher running: $st"
pass "health probe and watcher run"

sup_down
last=$(grep "stopped:" "$log" | tail -1)
[[ "$last" == *"stopped: roudi"* ]] || fail "RouDi was not stopped last: $(grep stopped: "$log")"
first=$(grep "stopped:" "$log" | head -1)
[[ "$first" == *"stopped: watch"* ]] || fail "the watcher was not stopped first: $(grep stopped: "$log")"
roudi_running && fail "RouDi still running after down"
pass "down stopped the watcher, capture, then RouDi last"
