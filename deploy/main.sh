#!/usr/bin/env bash
# README command (a): set up, build, and run the main job on the built-in default data:
# capture -> SLAM under the supervisor over shared memory, then the ATE against the sequence's
# ground truth and the frame rate. DF_DATA=<TUM folder> runs another sequence (fr3 intrinsics).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export DF_OUT="${DF_OUT:-$root/out/main}"
export DF_BUILD="${DF_BUILD:-$root/build}"
export DF_DATA="${DF_DATA:-$DF_BUILD/data/default}"
run_dir="$DF_OUT/run"
slam_out="$DF_OUT/slam"
# Check first, delete later: a second main.sh refuses before it touches any output of the first.
# The lock on fd 9 lasts as long as this script (the pipeline's programs do not inherit it).
mkdir -p "$DF_OUT"
exec 9>>"$DF_OUT/.main.lock"
if ! flock -n 9; then
  echo "main.sh: another main.sh (pid $(cat "$DF_OUT/.main.pid" 2>/dev/null || echo '?')) is running" \
    "with DF_OUT=$DF_OUT; wait for it or stop it (Ctrl-C there)" >&2
  exit 1
fi
echo $$ > "$DF_OUT/.main.pid"
trap 'echo "main.sh: interrupted; stopping the pipeline" >&2; exit 130' INT TERM
if [ -x /usr/bin/python3 ]; then deploy/dfsup --run-dir "$run_dir" check 9>&-; fi
if [ "$(id -u)" -eq 0 ]; then bash deploy/setup.sh; else sudo bash deploy/setup.sh; fi
bash deploy/build.sh
rm -rf "$slam_out"
deploy/dfsup --run-dir "$run_dir" up deploy/pipelines/default.pbtxt 9>&-
trap 'deploy/dfsup --run-dir "$run_dir" down >/dev/null || true' EXIT
status=0
deploy/dfsup --run-dir "$run_dir" wait slam --timeout 900 || status=$?
deploy/dfsup --run-dir "$run_dir" wait fusion --timeout 60 || true
echo
echo "== $(basename "$DF_DATA"): capture -> geoseg, detector (YOLOv5s), fusion -> slam (dynamics on: persons, objects and unknown movers left out of the static map); shared memory =="
grep -E "done:|bad frame" "$run_dir/logs/capture.log" | sed 's/^[^]]*\] //' || true
grep -E "stream ended" "$run_dir/logs/geoseg.log" "$run_dir/logs/detector.log" \
  "$run_dir/logs/fusion.log" | sed 's/^.*logs\///; s/\.log:[^]]*\] /: /' || true
grep -E "stream ended|tracking lost|recovered" "$run_dir/logs/slam.log" | sed 's/^[^]]*\] //' || true
if [ ! -s "$slam_out/trajectory.txt" ]; then
  echo "no trajectory was written; see $run_dir/logs/slam.log" >&2
  exit 1
fi
echo
if [ -f "$DF_DATA/groundtruth.txt" ]; then
  "$DF_BUILD"/bin/df_eval ate "$DF_DATA/groundtruth.txt" "$slam_out/trajectory.txt" \
    --json "$slam_out/ate.json" --plot "$slam_out/ate.png" || status=$?
fi
/usr/bin/python3 - "$slam_out/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
st = s["stages_ms"]
print(f"frames {s['frames']} (tracked {s['tracked']}, lost {s['lost']}); "
      f"{s['fps']:.1f} frames/s end to end in lockstep")
print("SLAM per frame, median / p95 ms: " + ", ".join(
    f"{k} {v['median']:.1f} / {v['p95']:.1f}" for k, v in st.items()))
print(f"map: {s['surfels']} surfels ({s['stable_surfels']} stable), {s['map_bytes'] / 2**20:.1f} MiB")
PY
# One line per object map: class, frames tracked, surfels; on generated data, the error of its
# trajectory against the ground-truth object of its class (the worlds aligned by the camera ATE,
# the object's own frame by its first pose: df_eval object --world --body-align), and its model
# against the true object's at 1 cm, placed by that first pose and after registration
# (df_eval recon --transform X^-1 --register).
if [ -f "$slam_out/objects.json" ]; then
  /usr/bin/python3 - "$slam_out" "$DF_DATA" "$DF_BUILD/bin/df_eval" <<'PY' || true
import json, os, subprocess, sys
out, data, df_eval = sys.argv[1:4]
objects = json.load(open(os.path.join(out, "objects.json")))["objects"]
gt = {}
if os.path.exists(os.path.join(data, "instances.json")):
    for i in json.load(open(os.path.join(data, "instances.json")))["instances"]:
        if i["kind"] == "rigid" and i.get("trajectory"):
            gt.setdefault(i["class_name"], []).append(i)
world = None
if os.path.exists(os.path.join(out, "ate.json")):
    a = json.load(open(os.path.join(out, "ate.json")))["ate"]["alignment_gt_T_est"]
    world = " ".join(str(v) for v in a["translation_m"] + a["quaternion_xyzw"])
def inverse_tum(m):
    """'tx ty tz qx qy qz qw' of the inverse of a rigid 4x4 matrix (rows)."""
    r = [[m[j][i] for j in range(3)] for i in range(3)]  # R^T
    t = [-sum(r[i][k] * m[k][3] for k in range(3)) for i in range(3)]
    tr = r[0][0] + r[1][1] + r[2][2]
    if tr > 0:
        s = 2 * (tr + 1) ** 0.5
        q = ((r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s, s / 4)
    elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
        s = 2 * (1 + r[0][0] - r[1][1] - r[2][2]) ** 0.5
        q = (s / 4, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s, (r[2][1] - r[1][2]) / s)
    elif r[1][1] > r[2][2]:
        s = 2 * (1 + r[1][1] - r[0][0] - r[2][2]) ** 0.5
        q = ((r[0][1] + r[1][0]) / s, s / 4, (r[1][2] + r[2][1]) / s, (r[0][2] - r[2][0]) / s)
    else:
        s = 2 * (1 + r[2][2] - r[0][0] - r[1][1]) ** 0.5
        q = ((r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, s / 4, (r[1][0] - r[0][1]) / s)
    return " ".join(repr(v) for v in t + list(q))
print(f"objects: {len(objects)} object map(s) (objects.json, objects/<id>.txt and .ply)")
for o in objects:
    line = (f"  object {o['id']} {o['class_name']}: tracked {o['frames_tracked']} frames "
            f"({o['first_frame']}..{o['last_frame']}), {o['surfels']} surfels, {o['state']}")
    # The ground-truth object of its class, or of its COCO supercategory for vehicles (the
    # detector calls the default data's toy car a truck as often as a car).
    vehicles = {"bicycle", "car", "motorbike", "aeroplane", "bus", "train", "truck", "boat"}
    same = gt.get(o["class_name"], [])
    if not same and o["class_name"] in vehicles:
        same = [i for c, l in gt.items() if c in vehicles for i in l]
    if world and len(same) == 1 and o["frames_tracked"] >= 2:
        j = os.path.join(out, f"eval_object_{o['id']}.json")
        r = subprocess.run([df_eval, "object", os.path.join(data, same[0]["trajectory"]),
                            os.path.join(out, o["trajectory"]), "--world", world, "--body-align",
                            "--json", j], capture_output=True)
        if r.returncode == 0:
            e = json.load(open(j))["object"]
            t = e["ate"]["translation_m"]["rmse"] * 100
            rot = e.get("rotation_deg", {}).get("rmse", float("nan"))
            line += f"; vs {same[0]['name']}: {t:.2f} cm, {rot:.2f} deg RMSE"
            model = same[0].get("model")
            x = e.get("alignment_est_object_T_gt_object", {}).get("matrix")
            if model and x and o.get("model") and os.path.exists(os.path.join(out, o["model"])):
                # The model in the true object's frame (X^-1), then registered onto it.
                j = os.path.join(out, f"eval_model_{o['id']}.json")
                r = subprocess.run([df_eval, "recon", os.path.join(data, model),
                                    os.path.join(out, o["model"]), "--threshold", "0.01",
                                    "--transform", inverse_tum(x), "--register", "--json", j],
                                   capture_output=True)
                if r.returncode == 0:
                    m = json.load(open(j))
                    a, g = m["reconstruction"], m["registered"]
                    line += (f"; model @1 cm accuracy/completeness {a['accuracy']:.2f}/"
                             f"{a['completeness']:.2f}, registered {g['accuracy']:.2f}/"
                             f"{g['completeness']:.2f}")
    print(line)
PY
fi
echo
echo "trajectory: $slam_out/trajectory.txt (TUM format)"
echo "map:        $slam_out/map.ply (open in MeshLab, CloudCompare or Open3D)"
echo "plots:      $slam_out/ate.png; figures: $slam_out/ate.json, $slam_out/summary.json"
echo "logs:       $run_dir/logs/"

# Beside it, what the dynamic handling buys: the same frames in one process with the static core
# alone (dynamics off: every pixel tracked and fused, moving things included), and, for
# generated sequences, with the ground-truth instance masks (SIMULATED segmentation, the bound).
offline_run() {  # NAME TITLE ARGS...
  local out="$DF_OUT/$1" title="$2"
  shift 2
  rm -rf "$out"
  echo
  echo "== the same frames, $title (df_slam offline $*) =="
  if "$DF_BUILD"/bin/df_slam offline "$DF_DATA" -o "$out" "$@" >"$out.log" 2>&1; then
    grep -E "^processed|^ATE" "$out.log" || true
  else
    echo "the run failed; see $out.log" >&2
    status=1
  fi
}
offline_run slam_dynamics_off "dynamics off: the static core alone" --dynamics off
if [ -d "$DF_DATA/instances" ]; then
  offline_run slam_gt_masks "SIMULATED segmentation: ground-truth instance masks" \
    --masks "$DF_DATA/instances"
fi
exit $status
