#!/usr/bin/env bash
# df_tap bridge while capture plays a generated sequence to SLAM: the real Foxglove WebSocket
# client (@foxglove/ws-protocol) connects, subscribes to the colour image and the transforms, and
# decodes them with the schemas the bridge advertised; every image's pixels equal the frame of the
# same capture time and every camera transform equals the pose SLAM published for it (both taken
# from a recording of the same run). A second bridge on the same port is refused with the reason.
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=30
make_sequence $N
: >"$TMP/bridge.out"  # made here: the loop below may read it before the bridge writes
"$BIN/df_tap" bridge --ns "$NS" --port 0 --jpeg 0 >"$TMP/bridge.out" 2>"$TMP/bridge.err" &
bridge=$!; pids+=($bridge)
port=""
for _ in $(seq 300); do
  port=$(sed -n 's|^bridge: ws://127.0.0.1:\([0-9]*\) .*|\1|p' "$TMP/bridge.out")
  [ -n "$port" ] && break
  kill -0 $bridge 2>/dev/null || fail "bridge exited: $(cat "$TMP/bridge.err")"
  sleep 0.1
done
[ -n "$port" ] || fail "the bridge did not say where it listens: $(cat "$TMP/bridge.out" "$TMP/bridge.err")"
pass "bridge listening on 127.0.0.1:$port"

set +e
timeout 30 "$BIN/df_tap" bridge --ns "$NS" --port "$port" >/dev/null 2>"$TMP/bridge2.err"
rc=$?
set -e
[ "$rc" -eq 1 ] && grep -q "127.0.0.1:$port" "$TMP/bridge2.err" \
  || fail "a second bridge on port $port: rc $rc, $(cat "$TMP/bridge2.err")"
pass "a second bridge on the same port is refused, naming it"

: >"$TMP/js.err"
node "$SRC/tests/js/bridge_check.mjs" "ws://127.0.0.1:$port" "$NS/foxglove" --images 10 \
  --transforms 10 --timeout-ms 120000 >"$TMP/js.json" 2>"$TMP/js.err" &
js=$!; pids+=($js)
for _ in $(seq 300); do
  grep -q subscribed "$TMP/js.err" && break
  kill -0 $js 2>/dev/null || fail "the Foxglove client exited: $(cat "$TMP/js.err")"
  sleep 0.1
done
grep -q subscribed "$TMP/js.err" || fail "the Foxglove client did not subscribe: $(cat "$TMP/js.err")"

"$BIN/df_tap" record -o "$TMP/rec.mcap" --ack rec --ns "$NS" --idle 5 --wait 30 \
  "$NS/frames" "$NS/camera_pose" >"$TMP/rec.out" 2>"$TMP/rec.err" &
rec=$!; pids+=($rec)
"$BIN/df_slam" run --set "dds { ns: \"$NS\" }" --set "output { dir: \"$TMP/out\" }" \
  --set 'use_segments: false' >"$TMP/slam.log" 2>&1 &
slam=$!; pids+=($slam)
capture_lockstep "$TMP/seq" slam rec
wait $slam || fail "slam failed: $(tail -5 "$TMP/slam.log")"
wait $rec || fail "recorder failed: $(tail -5 "$TMP/rec.err")"
wait $js || fail "the Foxglove client failed: $(cat "$TMP/js.err")"
node "$SRC/tests/js/foxglove_decode.mjs" "$TMP/rec.mcap" >"$TMP/rec.json" || fail "cannot decode the recording"

/usr/bin/python3 - "$TMP/js.json" "$TMP/rec.json" "$NS" <<'PY' || exit 1
import json, sys
got = json.load(open(sys.argv[1]))
rec = {c["topic"]: c["decodedMessages"] for c in json.load(open(sys.argv[2]))["channels"]}
ns = sys.argv[3]
def fail(m):
    print("FAIL:", m); sys.exit(1)
frames = {m["header"]["capture_ns"]: m for m in rec[f"{ns}/frames"]}
poses = {m["header"]["capture_ns"]: m for m in rec[f"{ns}/camera_pose"]}
if got["channels"]["image"]["schemaName"] != "foxglove::RawImage": fail(f"image schema {got['channels']}")
for im in got["images"]:
    f = frames.get(im["stamp"])
    if f is None: fail(f"image stamped {im['stamp']} matches no recorded frame")
    if (im["width"], im["height"], im["encoding"], im["step"]) != (640, 480, "rgb8", 1920): fail(f"image {im}")
    if im["sha256"] != f["rgbSha256"]: fail(f"image stamped {im['stamp']}: pixels differ from the frame's")
cams = [t for t in got["transforms"] if t["child"] == "camera"]
if len(cams) < 5: fail(f"{len(cams)} camera transforms of {len(got['transforms'])}")
for t in cams:
    p = poses.get(t["stamp"])
    if p is None: fail(f"transform stamped {t['stamp']} matches no recorded pose")
    w = p["world_T_camera"]
    sign = 1 if sum(a * b for a, b in zip(w["q"], t["q"])) >= 0 else -1
    if t["parent"] != "world" or any(abs(a - b) > 1e-9 for a, b in zip(w["t"], t["t"])) or \
       any(abs(a - sign * b) > 1e-6 for a, b in zip(w["q"], t["q"])):
        fail(f"transform {t} differs from the pose {w}")
print(f"ok: {len(got['images'])} images equal to their frames byte for byte, {len(cams)} camera transforms equal to the published poses")
PY
pass "Foxglove's client sees the pipeline through the bridge"
