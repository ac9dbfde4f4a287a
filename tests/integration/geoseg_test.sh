#!/usr/bin/env bash
# df_geoseg as a user runs it: behind capture in lockstep over shared memory, every frame is
# answered on geometric_segments with segments (status ok, labels in range), and the service
# leaves when the stream ends; a bad configuration value is named.
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=8
"$BIN/df_make_sequence" --preset default --out "$TMP/seq" --frames $N --no-models >/dev/null 2>&1 \
  || fail "df_make_sequence failed"

if "$BIN/df_geoseg" --set 'params { min_segment_pixels: 0 }' >"$TMP/bad.out" 2>&1; then
  fail "bad params accepted"
fi
grep -q "min_segment_pixels" "$TMP/bad.out" || fail "bad params not named: $(cat "$TMP/bad.out")"
pass "bad configuration named"

"$BIN/df_tap" echo "$NS/geometric_segments" -n $N --items 4 >"$TMP/echo.out" 2>"$TMP/echo.err" &
echo_pid=$!; pids+=($echo_pid)
"$BIN/df_geoseg" --set "dds { ns: \"$NS\" }" >"$TMP/geoseg.log" 2>&1 &
geoseg=$!; pids+=($geoseg)
"$BIN/df_capture" "$TMP/seq" --set "dds { ns: \"$NS\" }" --set 'playback: LOCKSTEP' \
  --set 'lockstep_stages: "geoseg"' --set 'start_wait_s: 20' >"$TMP/capture.log" 2>&1 \
  || fail "capture failed: $(tail "$TMP/capture.log")"
grep -q "0 lockstep timeouts" "$TMP/capture.log" || fail "lockstep timeouts: $(grep done: "$TMP/capture.log")"
wait $geoseg || fail "geoseg failed: $(tail "$TMP/geoseg.log")"
grep -q "$N frames segmented, 0 skipped, 0 failed" "$TMP/geoseg.log" || fail "geoseg: $(tail -3 "$TMP/geoseg.log")"
wait $echo_pid || fail "echo failed: $(cat "$TMP/echo.err")"
/usr/bin/python3 - "$TMP/echo.out" $N <<'PY' || fail "geometric_segments content: $(head -c 2000 "$TMP/echo.out")"
import re, sys
text = open(sys.argv[1]).read()
n = int(sys.argv[2])
seqs = [int(s) for s in re.findall(r"\bseq:\s*(\d+)", text)]
counts = [int(c) for c in re.findall(r"segment_count:\s*(\d+)", text)]
status = re.findall(r"status:\s*(\w+)", text)
assert sorted(seqs) == list(range(n)), seqs
assert len(counts) == n and all(c >= 3 for c in counts), counts
assert len(status) == n and all(s in ("OK", "FRAME_OK") for s in status), status
print(f"ok: {n} frames, segments per frame {counts}")
PY
pass "geoseg: $N frames answered on geometric_segments in lockstep"
