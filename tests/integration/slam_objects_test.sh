#!/usr/bin/env bash
# Object maps in the SLAM service: generated room4 (a car drives through the room, a suitcase
# slides in front of it) behind the segmentation services (SIMULATED detector) in lockstep over
# shared memory. SLAM publishes object_poses for every frame; the car and the suitcase each get
# one object map of their class that is tracked, and the run's objects.json and
# objects/<id>.txt hold them.
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=30
"$BIN/df_make_sequence" --preset room4 --out "$TMP/seq" --frames $N --no-models >/dev/null 2>&1 \
  || fail "df_make_sequence failed"
"$BIN/df_tap" echo "$NS/object_poses" -n $N --items 8 --depth 64 >"$TMP/echo.out" 2>"$TMP/echo.err" &
echo_pid=$!; pids+=($echo_pid)
start_segmentation "$TMP/seq"
"$BIN/df_slam" run --set "dds { ns: \"$NS\" }" --set "output { dir: \"$TMP/out\" log_every: 1 }" \
  --set 'segments_deadline_ms: 2000' >"$TMP/slam.log" 2>&1 &
slam=$!; pids+=($slam)
capture_lockstep "$TMP/seq" slam
wait $slam || fail "slam failed: $(tail -5 "$TMP/slam.log")"
timeout 60 bash -c "while kill -0 $echo_pid 2>/dev/null; do sleep 0.2; done" \
  || fail "object_poses: $(grep -c 'header:' "$TMP/echo.out") of $N messages"
/usr/bin/python3 - "$TMP/echo.out" "$TMP/out/objects.json" $N <<'PY' || fail "object_poses: $(tail -c 1500 "$TMP/echo.out")"
import json, re, sys
text, n = open(sys.argv[1]).read(), int(sys.argv[3])
msgs = text.split("header:")[1:]
seqs = sorted(int(re.search(r"\bseq:\s*(\d+)", m).group(1)) for m in msgs)
assert seqs == list(range(n)), f"object_poses for frames {seqs}"
tracked, classes = {}, {}
for m in msgs:
    for obj in m.split("- object_id:")[1:]:
        oid = int(obj.split()[0])
        cls = int(re.search(r"class_id:\s*(-?\d+)", obj).group(1))
        # class -1: an unknown mover's map made from motion segmentation (objects.from_motion;
        # room4's drum has no COCO class)
        assert cls in (2, 28, -1), f"object {oid} of class {cls}: room4's rigid known movers are the car and the suitcase"
        classes[oid] = cls
        if re.search(r"tracked:\s*true", obj):
            tracked[oid] = tracked.get(oid, 0) + 1
known = {o: f for o, f in tracked.items() if classes[o] != -1}
assert sorted(classes[o] for o in known) == [2, 28], f"one car and one suitcase map expected, tracked: {tracked} of classes {classes}"
for oid, frames in known.items():
    assert frames >= n // 2, f"object {oid} (class {classes[oid]}) was tracked in {frames} of {n} frames"
table = json.load(open(sys.argv[2]))["objects"]
for oid, name in ((o, {2: "car", 28: "suitcase"}[classes[o]]) for o in known):
    assert [o["id"] for o in table if o["class_name"] == name] == [oid], table
    row = next(o for o in table if o["id"] == oid)
    assert sum(1 for _ in open(sys.argv[2].replace("objects.json", row["trajectory"]))) >= tracked[oid]
print(f"ok: objects tracked {tracked} in {n} frames (classes {classes}); objects.json lists them")
PY
pass "object_poses for every frame; the car and the suitcase each have one tracked object map"
