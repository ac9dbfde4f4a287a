#!/usr/bin/env bash
# The command line, without DDS. df_detector --image on darknet's sample photos finds the dog in
# dog.jpg and the person and horse in person.jpg, prints class, score and box, and writes each
# picture with its boxes drawn; a missing or corrupt picture is named, with the good pictures of
# the same call still done. df_geoseg --depth and df_fusion --color --depth on one generated frame:
# segments drawn, the person's mask within IoU 0.5 of the truth; bad files named.
source "$(dirname "$0")/lib.sh"
photos=/usr/share/darknet/data
model=""
for m in "${DF_MODELS_DIR:-/nonexistent}" "$HOME/.cache/detectfusion/models" /usr/local/share/detectfusion/models; do
  [ -f "$m/yolov5s/model.json" ] && { model="$m/yolov5s"; break; }
done
if [ ! -f "$photos/dog.jpg" ] || [ -z "$model" ]; then
  echo "SKIP: needs darknet's sample photos in $photos and the YOLOv5s model (bash deploy/setup.sh)"
  exit 77
fi

# A class's line in the output of one picture: "  <class> <score>  x X y Y w W h H".
has_class() {  # has_class OUTPUT PICTURE CLASS MIN_SCORE
  awk -v pic="$2" -v cls="$3" -v min="$4" '
    /^[^ ]/ { inside = index($0, pic ":") == 1 }
    inside && $1 == cls && $2 + 0 >= min + 0 { found = 1 }
    END { exit !found }' <<<"$1"
}

out=$("$BIN/df_detector" --image "$photos/dog.jpg" "$photos/person.jpg" --out "$TMP/pictures" 2>"$TMP/err") \
  || fail "df_detector --image failed: $(cat "$TMP/err")"
echo "$out"
has_class "$out" "$photos/dog.jpg" dog 0.5 || fail "no dog found in dog.jpg"
has_class "$out" "$photos/person.jpg" person 0.5 || fail "no person found in person.jpg"
has_class "$out" "$photos/person.jpg" horse 0.5 || fail "no horse found in person.jpg"
grep -q "^$photos/dog.jpg: 768x576" <<<"$out" || fail "dog.jpg's size not printed as 768x576"
for stem in dog person; do
  pic="$TMP/pictures/${stem}_detections.jpg"
  [ -s "$pic" ] || fail "$pic not written"
  [ "$(head -c 3 "$pic" | od -An -tx1 | tr -d ' ')" = ffd8ff ] || fail "$pic is not a JPEG"
done
pass "dog, person and horse found; pictures with boxes written"

# The dog's box: near darknet's published one (x 133 y 220 w 179 h 322) within 20 px a side.
read -r x y w h < <(awk '/dog.jpg:/ {inside=1; next} /^[^ ]/ {inside=0}
  inside && $1 == "dog" {print $4, $6, $8, $10; exit}' <<<"$out")
for v in "$((x - 133))" "$((y - 220))" "$((x + w - 312))" "$((y + h - 542))"; do
  [ "${v#-}" -le 20 ] || fail "dog box $x $y $w $h is more than 20 px from 133 220 312 542"
done
pass "dog box within 20 px of the truth"

# Bad pictures: named, exit 1, and the good picture given with them still done.
head -c 5000 "$photos/dog.jpg" >"$TMP/truncated.jpg"
echo "not a picture" >"$TMP/text.jpg"
set +e
out=$("$BIN/df_detector" --image "$TMP/missing.jpg" "$TMP/text.jpg" "$photos/person.jpg" \
  --out "$TMP/pictures2" 2>"$TMP/err")
rc=$?
set -e
[ "$rc" -eq 1 ] || fail "bad pictures: exit $rc, expected 1"
grep -q "$TMP/missing.jpg: no such picture file" "$TMP/err" || fail "missing file not named: $(cat "$TMP/err")"
grep -q "$TMP/text.jpg: not a picture OpenCV can read" "$TMP/err" || fail "corrupt file not named: $(cat "$TMP/err")"
has_class "$out" "$photos/person.jpg" person 0.5 || fail "the good picture after two bad ones was not done"
pass "missing and corrupt pictures named; the good one still done"

# The simulated detector reads ground truth, not pictures: refused with the reason.
set +e
"$BIN/df_detector" --image "$photos/dog.jpg" --set 'model: "simulated"' --set "sim_sequence: \"$TMP\"" >/dev/null 2>"$TMP/err"
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "needs a YOLO model" "$TMP/err" || fail "simulated model with --image: rc $rc, $(cat "$TMP/err")"
pass "--image with the simulated detector refused with its reason"

# One frame of a generated sequence (frame 29: the person in full view).
make_sequence 30
frame=1.966667
[ -f "$TMP/seq/depth/$frame.png" ] || fail "the generated sequence has no frame $frame"
out=$("$BIN/df_geoseg" --depth "$TMP/seq/depth/$frame.png" --color "$TMP/seq/rgb/$frame.png" \
  --out "$TMP/geoseg" 2>"$TMP/err") || fail "df_geoseg --depth failed: $(cat "$TMP/err")"
echo "$out"
read -r segments cover < <(sed -n 's/.*: 640x480, \([0-9]*\) geometric segments covering \([0-9.]*\) %.*/\1 \2/p' <<<"$out")
[ "${segments:-0}" -ge 3 ] || fail "df_geoseg found ${segments:-no} segments, expected at least 3"
awk -v c="$cover" 'BEGIN { exit !(c >= 20) }' || fail "segments cover $cover % of the frame, expected >= 20 %"
pic="$TMP/geoseg/${frame}_segments.png"
[ "$(head -c 4 "$pic" | od -An -tx1 | tr -d ' ')" = 89504e47 ] || fail "$pic is not a PNG"
pass "df_geoseg --depth: $segments segments covering $cover %, picture written"

out=$("$BIN/df_fusion" --color "$TMP/seq/rgb/$frame.png" --depth "$TMP/seq/depth/$frame.png" \
  --out "$TMP/fusion" 2>"$TMP/err") || fail "df_fusion --color --depth failed: $(cat "$TMP/err")"
echo "$out"
grep -Eq "^  #[0-9]+ +person +non_rigid" <<<"$out" || fail "df_fusion printed no person instance"
mkdir -p "$TMP/pred"
cp "$TMP/fusion/${frame}_instance_labels.png" "$TMP/pred/$frame.png" || fail "no label image written"
"$BIN/df_eval" seg "$TMP/seq" "$TMP/pred" --skip-missing --json "$TMP/seg.json" >/dev/null \
  || fail "df_eval seg failed on the label image"
iou=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1]))["segmentation"]["instances"]
print(next(i["mean_iou"] for i in d if i["class_name"] == "person"))' "$TMP/seg.json")
awk -v v="$iou" 'BEGIN { exit !(v >= 0.5) }' || fail "the person's mask has IoU $iou with the truth, expected >= 0.5"
pass "df_fusion --color --depth: the person's mask has IoU $iou with the truth"

# Bad files: named, exit 1 (or 2 for a flag that is wrong).
expect_error() {  # expect_error RC PATTERN COMMAND...
  local want="$1" pattern="$2"; shift 2
  set +e; "$@" >/dev/null 2>"$TMP/err"; local rc=$?; set -e
  [ "$rc" -eq "$want" ] && grep -q -- "$pattern" "$TMP/err" \
    || fail "$*: rc $rc (expected $want), stderr: $(cat "$TMP/err") (expected: $pattern)"
}
expect_error 1 "$TMP/none.png: file does not exist" "$BIN/df_geoseg" --depth "$TMP/none.png"
expect_error 1 "$TMP/seq/rgb/$frame.png: expected a 16-bit 1-channel depth image" \
  "$BIN/df_geoseg" --depth "$TMP/seq/rgb/$frame.png"
expect_error 1 "$TMP/text.jpg: cannot decode image" \
  "$BIN/df_fusion" --color "$TMP/text.jpg" --depth "$TMP/seq/depth/$frame.png"
expect_error 2 "needs --color" "$BIN/df_fusion" --depth "$TMP/seq/depth/$frame.png"
expect_error 1 "unknown intrinsics preset 'fr9'" "$BIN/df_geoseg" --depth "$TMP/seq/depth/$frame.png" --preset fr9
pass "missing, wrong-type and corrupt frame files and a bad preset named"

# df_slam offline --foxglove: the run as Foxglove views in one MCAP file (zstd, JPEG), decoded by
# Foxglove's own reader; the camera transforms are the trajectory the run wrote.
"$BIN/df_slam" offline "$TMP/seq" -o "$TMP/offline" --detector simulated --max-frames 12 \
  --set 'map_cloud_every_frames: 5' --foxglove "$TMP/run.mcap" >"$TMP/offline.out" 2>"$TMP/offline.err" \
  || fail "df_slam offline --foxglove failed: $(tail -3 "$TMP/offline.err")"
node "$SRC/tests/js/foxglove_decode.mjs" "$TMP/run.mcap" >"$TMP/run.json" \
  || fail "Foxglove's decoder rejects the offline run's views"
/usr/bin/python3 - "$TMP/run.json" "$TMP/offline/trajectory.txt" <<'PY' || exit 1
import json, sys
ch = {c["topic"]: c for c in json.load(open(sys.argv[1]))["channels"]}
traj = {round(float(l.split()[0]) * 1e9): [float(x) for x in l.split()[1:]] for l in open(sys.argv[2]) if l.strip() and not l.startswith("#")}
def fail(m):
    print("FAIL:", m); sys.exit(1)
want = {"color": "foxglove::CompressedImage", "depth": "foxglove::RawImage", "masks": "foxglove::CompressedImage",
        "detections": "foxglove::ImageAnnotations", "tf": "foxglove::FrameTransform", "scene": "foxglove::SceneUpdate",
        "map": "foxglove::PointCloud"}
for k, s in want.items():
    c = ch.get(f"df/foxglove/{k}")
    if c is None or c["schema"] != s: fail(f"df/foxglove/{k}: {c and c['schema']}, want {s}")
if ch["df/foxglove/color"]["messages"] != 12 or ch["df/foxglove/depth"]["messages"] != 12: fail("not 12 images")
if any(m["format"] != "jpeg" or m["dataLength"] < 1000 for m in ch["df/foxglove/color"]["decodedMessages"]): fail("colour not JPEG")
cams = [m for m in ch["df/foxglove/tf"]["decodedMessages"] if m["child_frame_id"] == "camera"]
if len(cams) != 12: fail(f"{len(cams)} camera transforms for 12 frames")
for m in cams:
    stamp = m["timestamp"]["sec"] * 10**9 + m["timestamp"]["nsec"]
    key = min(traj, key=lambda k: abs(k - stamp))
    if abs(key - stamp) > 1000 or any(abs(a - b) > 1e-5 for a, b in zip(traj[key][:3], m["translation"])):
        fail(f"transform at {stamp} {m['translation']} is not the trajectory's {traj.get(key)}")
maps = ch["df/foxglove/map"]["decodedMessages"]
if len(maps) < 2 or maps[-1]["dataLength"] < 16 * 1000: fail(f"map clouds: {[m['dataLength'] for m in maps]}")
print(f"ok: 12 frames of views; camera transforms equal the trajectory; {len(maps)} map clouds")
PY
pass "df_slam offline --foxglove writes the run's views"
