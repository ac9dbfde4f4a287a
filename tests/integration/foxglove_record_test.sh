#!/usr/bin/env bash
# df_tap record --foxglove beside the SLAM pipeline (geometric segmentation, SIMULATED detector,
# fusion, SLAM) in lockstep over a generated room4 sequence: the recording holds Foxglove's own
# schemas, and Foxglove's IDL parser and CDR reader (the code Studio runs) decode every message,
# field by field equal to the pipeline's own samples in the same file: colour and depth pixels
# byte for byte, boxes, the camera's and objects' transforms, the masks, the map as a point cloud
# and the objects' boxes in the scene.
source "$(dirname "$0")/lib.sh"
roudi_running || fail "no RouDi: run through ctest (fixture roudi)"
N=20
"$BIN/df_make_sequence" --preset room4 --out "$TMP/seq" --frames $N --no-models >/dev/null 2>&1 \
  || fail "df_make_sequence failed"
"$BIN/df_tap" record -o "$TMP/rec.mcap" --foxglove --ack rec --ns "$NS" --idle 5 --wait 30 \
  "$NS/frames" "$NS/detections" "$NS/object_segments" "$NS/camera_pose" "$NS/object_poses" "$NS/map_cloud" \
  >"$TMP/rec.out" 2>"$TMP/rec.err" &
rec=$!; pids+=($rec)
start_segmentation "$TMP/seq"
"$BIN/df_slam" run --set "dds { ns: \"$NS\" }" --set "output { dir: \"$TMP/out\" }" \
  --set 'segments_deadline_ms: 2000' --set 'map_cloud_every_frames: 5' >"$TMP/slam.log" 2>&1 &
slam=$!; pids+=($slam)
capture_lockstep "$TMP/seq" slam rec
wait $slam || fail "slam failed: $(tail -5 "$TMP/slam.log")"
wait $rec || fail "recorder failed: $(tail -5 "$TMP/rec.err")"
cat "$TMP/rec.out"

node "$SRC/tests/js/foxglove_decode.mjs" "$TMP/rec.mcap" >"$TMP/fox.json" \
  || fail "Foxglove's decoder rejects the recording"
/usr/bin/python3 - "$TMP/fox.json" "$NS" $N <<'PY' || exit 1
import json, sys
channels = {c["topic"]: c for c in json.load(open(sys.argv[1]))["channels"]}
ns, n = sys.argv[2], int(sys.argv[3])
def fail(msg):
    print("FAIL:", msg); sys.exit(1)
def msgs(topic):
    if topic not in channels: fail(f"no channel {topic}; channels: {sorted(channels)}")
    return channels[topic]["decodedMessages"]
def by_seq(topic): return {m["sequence"]: m for m in msgs(topic)}
schemas = {t: c["schema"] for t, c in channels.items()}
want = {"color": "foxglove::RawImage", "depth": "foxglove::RawImage", "detections": "foxglove::ImageAnnotations",
        "masks": "foxglove::RawImage", "tf": "foxglove::FrameTransform", "scene": "foxglove::SceneUpdate"}
for k, s in want.items():
    if schemas.get(f"{ns}/foxglove/{k}") != s: fail(f"{ns}/foxglove/{k} has schema {schemas.get(f'{ns}/foxglove/{k}')}, want {s}")

frames, colour, depth = by_seq(f"{ns}/frames"), by_seq(f"{ns}/foxglove/color"), by_seq(f"{ns}/foxglove/depth")
if sorted(frames) != list(range(n)): fail(f"frames recorded: {sorted(frames)}")
for seq, f in frames.items():
    c, d = colour.get(seq), depth.get(seq)
    if c is None or d is None: fail(f"frame {seq}: no Foxglove colour or depth image")
    stamp = int(f["header"]["capture_ns"])
    for img, enc, step, sha in ((c, "rgb8", 1920, f["rgbSha256"]), (d, "16UC1", 1280, f["depthSha256"])):
        if (img["width"], img["height"], img["encoding"], img["step"]) != (640, 480, enc, step):
            fail(f"frame {seq}: {enc} image is {img['width']}x{img['height']} {img['encoding']} step {img['step']}")
        if img["dataSha256"] != sha: fail(f"frame {seq}: {enc} pixels differ from the frame's")
        if img["timestamp"]["sec"] * 10**9 + img["timestamp"]["nsec"] != stamp: fail(f"frame {seq}: {enc} stamp")
        if img["frame_id"] != "camera": fail(f"frame {seq}: frame_id {img['frame_id']}")
print(f"ok: {n} colour and depth images byte-identical to the frames, stamped with their capture time")

dets, ann = by_seq(f"{ns}/detections"), by_seq(f"{ns}/foxglove/detections")
boxes = 0
for seq, d in dets.items():
    if not d["boxes"]: continue
    a = ann.get(seq)
    if a is None: fail(f"frame {seq}: {len(d['boxes'])} detections but no annotations")
    if len(a["points"]) != len(d["boxes"]) or len(a["texts"]) != len(d["boxes"]): fail(f"frame {seq}: annotations {a}")
    for (x, y, w, h, cls), p in zip(d["boxes"], a["points"]):
        corners = [[x, y], [x + w, y], [x + w, y + h], [x, y + h]]
        if p["type"] != 2 or any(abs(u - v) > 1e-3 for c, q in zip(corners, p["points"]) for u, v in zip(c, q)):
            fail(f"frame {seq}: box {x, y, w, h} drawn as {p}")
        boxes += 1
if boxes == 0: fail("no detection box in the recording")
print(f"ok: {boxes} detector boxes drawn as closed outlines at their pixels, with labels")

poses = by_seq(f"{ns}/camera_pose")
tf = [m for m in msgs(f"{ns}/foxglove/tf")]
cam = {m["sequence"]: m for m in tf if m["child_frame_id"] == "camera"}
checked = 0
for seq, p in poses.items():
    if p["state"] != 0: continue
    t = cam.get(seq)
    if t is None or t["parent_frame_id"] != "world": fail(f"frame {seq}: no world->camera transform")
    q, tq = p["world_T_camera"]["q"], t["rotation"]
    sign = 1 if sum(a * b for a, b in zip(q, tq)) >= 0 else -1
    if any(abs(a - b) > 1e-9 for a, b in zip(p["world_T_camera"]["t"], t["translation"])) or \
       any(abs(a - sign * b) > 1e-6 for a, b in zip(q, tq)):
        fail(f"frame {seq}: transform {t} differs from the pose {p['world_T_camera']}")
    checked += 1
if checked < n - 2: fail(f"only {checked} camera transforms of {n} frames")
objects = by_seq(f"{ns}/object_poses")
obj_tf = {(m["sequence"], m["child_frame_id"]): m for m in tf if m["child_frame_id"].startswith("object_")}
seen = 0
for seq, o in objects.items():
    for obj in o["objects"]:
        t = obj_tf.get((seq, f"object_{obj['object_id']}"))
        if t is None: fail(f"frame {seq}: no transform for object {obj['object_id']}")
        if any(abs(a - b) > 1e-9 for a, b in zip(obj["world_T_object"]["t"], t["translation"])): fail(f"object transform {t}")
        seen += 1
if seen == 0: fail("no object transform (room4's car and suitcase get object maps)")
print(f"ok: {checked} camera and {seen} object transforms equal to the published poses")

masks, segs = by_seq(f"{ns}/foxglove/masks"), by_seq(f"{ns}/object_segments") if f"{ns}/object_segments" in channels else {}
if len(masks) < n // 2: fail(f"{len(masks)} mask images for {n} frames")
if any((m["width"], m["height"], m["encoding"]) != (640, 480, "rgb8") for m in masks.values()): fail("mask image size/encoding")
different = sum(1 for s, m in masks.items() if s in colour and m["dataSha256"] != colour[s]["dataSha256"])
if different == 0: fail("no mask image differs from its colour image: nothing tinted")
print(f"ok: {len(masks)} mask images, {different} with instances tinted over the colour")

scene = msgs(f"{ns}/foxglove/scene")
last = scene[-1]
path = [e for e in last["entities"] if e["id"] == "camera_path"]
if not path or path[0]["lines"][0]["points"] < n - 3 or path[0]["frame_id"] != "world":
    fail(f"the last scene update has no camera path of the run: {last}")
if not last["deletions"] or last["deletions"][0]["type"] != 1: fail("scene updates do not replace the previous scene")
print(f"ok: the scene holds the camera path ({path[0]['lines'][0]['points']} poses)")

clouds, fox_map = by_seq(f"{ns}/map_cloud"), by_seq(f"{ns}/foxglove/map")
if len(clouds) < n // 5 - 1: fail(f"{len(clouds)} map clouds in {n} frames at one every 5")
for seq, c in clouds.items():
    f = fox_map.get(seq)
    if f is None: fail(f"map cloud of frame {seq} has no Foxglove point cloud")
    names = [(x["name"], x["offset"], x["type"]) for x in f["fields"]]
    if names != [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("red", 12, 1), ("green", 13, 1), ("blue", 14, 1), ("alpha", 15, 1)]:
        fail(f"point cloud fields {names}")
    if f["point_stride"] != 16 or f["dataLength"] != 16 * c["point_count"] or f["frame_id"] != "world":
        fail(f"frame {seq}: point cloud of {f['dataLength']} bytes for {c['point_count']} points")
    if any(abs(a - b) > 1e-6 for p, q in zip(c["first_points"], f["first_points"]) for a, b in zip(p, q)):
        fail(f"frame {seq}: points {f['first_points']} differ from the map's {c['first_points']}")
last_cloud = clouds[max(clouds)]
if last_cloud["point_count"] < 1000: fail(f"the last map cloud has {last_cloud['point_count']} points")
boxes = {e["id"] for e in last["entities"] if e["cubes"]}
want_boxes = {f"object_{i}" for i in last_cloud["objects"]}
if not want_boxes or not want_boxes <= boxes: fail(f"object boxes {boxes} in the scene, want {want_boxes}")
print(f"ok: {len(clouds)} map clouds as point clouds (last {last_cloud['point_count']} points); object boxes {sorted(boxes)} in the scene")
PY
pass "Foxglove views recorded and decoded by Foxglove's own reader"
