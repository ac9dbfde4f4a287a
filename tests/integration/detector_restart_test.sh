#!/usr/bin/env bash
# The segmentation services under the supervisor, capture at the sequence's 30 Hz: the detector
# (simulated) is killed mid-stream; object_segments still answers every frame (those without
# detections marked so), the supervisor restarts the detector, and detections come back.
source "$(dirname "$0")/lib.sh"
if roudi_running; then
  echo "SKIP: a RouDi is already running on this machine; this test needs to start its own under dfsup"
  exit 77
fi
N=120
"$BIN/df_make_sequence" --preset default --out "$TMP/seq" --frames $N --no-models >/dev/null 2>&1
cat > "$TMP/pipeline.pbtxt" <<PB
name: "detector-restart-test"
service { name: "geoseg" binary: "df_geoseg" args: ["--set", "dds { ns: \"\${DF_NS}\" }"] priority: 50 }
service {
  name: "detector"
  binary: "df_detector"
  args: ["--set", "dds { ns: \"\${DF_NS}\" }", "--set", "model: \"simulated\"",
         "--set", "sim_sequence: \"\${DF_DATA}\"", "--set", "sim_latency_ms: 10"]
  priority: 50
}
service { name: "fusion" binary: "df_fusion" args: ["--set", "dds { ns: \"\${DF_NS}\" }"] priority: 50 }
PB
SUP="$SRC/deploy/dfsup --run-dir $TMP/run"
$SUP up "$TMP/pipeline.pbtxt" --var "DF_DATA=$TMP/seq" --var "DF_NS=$NS" --var "DF_OUT=$TMP/out" \
  --var "DF_BUILD=$(dirname "$BIN")"
trap '$SUP down >/dev/null 2>&1 || true; cleanup' EXIT
# Deep history: fusion answers every waiting frame at once when the detector dies.
"$BIN/df_tap" echo "$NS/object_segments" -n $N --items 1 --depth 256 >"$TMP/echo.out" 2>"$TMP/echo.err" &
echo_pid=$!; pids+=($echo_pid)
sleep 2  # services and the echo discover each other
"$BIN/df_capture" "$TMP/seq" --config "$SRC/deploy/config/capture_realtime.pbtxt" \
  --set "dds { ns: \"$NS\" }" --set "loops: 1" >"$TMP/capture.log" 2>&1 &
cap=$!; pids+=($cap)
sleep 1.5
pid=$($SUP status | awk '$1=="detector" {print $4}')
[ -n "$pid" ] || fail "no detector running: $($SUP status)"
kill -KILL "$pid"
for _ in $(seq 100); do
  new=$($SUP status | awk '$1=="detector" && $2=="RUNNING" {print $4}')
  [ -n "$new" ] && [ "$new" != "$pid" ] && break
  sleep 0.05
done
[ -n "${new:-}" ] && [ "$new" != "$pid" ] || fail "detector not restarted after kill -9 ($($SUP status))"
pass "detector killed (pid $pid) and restarted by the supervisor (pid $new)"
wait $cap || fail "capture failed: $(tail -3 "$TMP/capture.log")"
missing() {  # the sequence numbers echo has not printed
  /usr/bin/python3 -c 'import re,sys; got={int(s) for s in re.findall(r"\bseq:\s*(\d+)", open(sys.argv[1]).read())}; print(sorted(set(range(int(sys.argv[2]))) - got))' "$TMP/echo.out" $N
}
timeout 30 bash -c "while kill -0 $echo_pid 2>/dev/null; do sleep 0.2; done" ||
  fail "object_segments stopped: $(grep -c header: "$TMP/echo.out") of $N frames; missing $(missing); fusion: $(grep -v '^ *$' "$TMP/run/logs/fusion.log" | tail -5); geoseg: $(tail -3 "$TMP/run/logs/geoseg.log")"
/usr/bin/python3 - "$TMP/echo.out" $N <<'PY' || fail "object_segments: $(tail -c 1000 "$TMP/echo.out")"
import re, sys
text, n = open(sys.argv[1]).read(), int(sys.argv[2])
msgs = text.split("header:")[1:]
seqs = [int(re.search(r"\bseq:\s*(\d+)", m).group(1)) for m in msgs]
assert sorted(seqs) == list(range(n)), f"{len(seqs)} messages, missing {sorted(set(range(n)) - set(seqs))[:10]}"
used = [re.search(r"detections_used:\s*(\w+)", m).group(1) == "true" for m in sorted(msgs, key=lambda m: int(re.search(r"\bseq:\s*(\d+)", m).group(1)))]
first_gap = used.index(False) if False in used else -1
assert first_gap > 0, "never without detections"
assert any(used[first_gap:]), "detections never came back after the restart"
print(f"ok: {n} frames answered; without detections: {used.count(False)} (first at frame {first_gap}); with: {used.count(True)}")
PY
pass "object_segments answered every frame through the detector's crash; detections came back"
