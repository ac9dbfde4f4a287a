#!/usr/bin/env bash
# Capture under the supervisor: RouDi starts first; tap hz shows the sequence's 30 Hz; tap list
# and echo see the topic; a killed capture is restarted; down stops the services, RouDi last.
source "$(dirname "$0")/lib.sh"
if roudi_running; then
  echo "SKIP: a RouDi is already running on this machine; this test needs to start its own under dfsup"
  exit 77
fi
"$BIN/df_make_sequence" --preset default --out "$TMP/seq" --frames 30 >/dev/null 2>&1
cat > "$TMP/pipeline.pbtxt" <<PB
name: "supervisor-test"
service {
  name: "capture"
  binary: "df_capture"
  config: "deploy/config/capture_realtime.pbtxt"
  args: ["\${DF_DATA}", "--set", "dds { ns: \"\${DF_NS}\" }"]
}
PB
SUP="$SRC/deploy/dfsup --run-dir $TMP/run"
$SUP up "$TMP/pipeline.pbtxt" --var "DF_DATA=$TMP/seq" --var "DF_NS=$NS" --var "DF_OUT=$TMP/out"
trap '$SUP down >/dev/null 2>&1 || true; cleanup' EXIT
log="$TMP/run/supervisord.log"
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
pass "tap echo prints a frame header"

pid=$($SUP status | awk '$1=="capture" {print $4}')
kill -KILL "$pid"
for _ in $(seq 100); do
  new=$($SUP status | awk '$1=="capture" && $2=="RUNNING" {print $4}')
  [ -n "$new" ] && [ "$new" != "$pid" ] && break
  sleep 0.1
done
[ -n "${new:-}" ] && [ "$new" != "$pid" ] || fail "capture was not restarted after kill -9 ($($SUP status))"
grep -q "exited: capture (terminated by SIGKILL; not expected)" "$log" || fail "no crash in supervisord log"
pass "capture killed (pid $pid) and restarted (pid $new)"
after=$(timeout 60 "$BIN/df_tap" hz "$NS/frames" --wait 15 --duration 2 2>"$TMP/hz2.err") \
  || fail "tap hz after the restart exited with $?: $(tail -5 "$TMP/hz2.err")"
[[ "$after" == *"average rate"* ]] || fail "no frames after restart: $after"
pass "frames flow again after the restart"

$SUP down
trap cleanup EXIT
last=$(grep "stopped:" "$log" | tail -1)
[[ "$last" == *"stopped: roudi"* ]] || fail "RouDi was not stopped last: $(grep stopped: "$log")"
roudi_running && fail "RouDi still running after down"
pass "down stopped capture, then RouDi last"
