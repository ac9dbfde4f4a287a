#!/usr/bin/env bash
# Cost of object maps with 1, 3 and 5 objects in view (issue 12; figures in docs/objects.md,
# "Cost"): generated cars_1, cars_3 and cars_5 (toy cars driving to and fro in front of a
# hand-held camera, all in view), df_slam offline with the sequences' ground-truth masks (so
# exactly those cars are the rigid instances: the cost of the object maps, not of detection),
# once with object maps and once without (`objects { enabled: false }`: part 1's cost).
# Prints per run the per-frame medians of the three object stages and of the whole frame, the
# mean number of objects tracked per frame, and the cost per tracked object.
# usage: tests/bench/run_object_cost_bench.sh   (environment: FRAMES, default 150)
# Needs a build (bash deploy/build.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$root/build/bin"
frames="${FRAMES:-150}"
out="$root/out/bench/object_cost"
mkdir -p "$out"

report() {  # name dir
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, re, statistics, sys
name, d = sys.argv[1], sys.argv[2]
objects, total = [], []
for line in open(f"{d}/timings.log"):
    f = dict(re.findall(r"(\w+)=([-0-9.]+)", line))
    if "total" not in f or int(f.get("seq", 0)) < 5:  # the first frames create the maps
        continue
    objects.append(sum(float(f.get(k, 0)) for k in ("objects_predict", "objects_track", "objects_map")))
    total.append(float(f["total"]))
s = json.load(open(f"{d}/summary.json"))
tracked = 0
try:
    tracked = sum(o["frames_tracked"] for o in json.load(open(f"{d}/objects.json"))["objects"])
except FileNotFoundError:
    pass
per_frame = tracked / max(1, s["frames"])
mo = statistics.median(objects)
print(f"{name:28s} objects {mo:6.1f} ms  frame {statistics.median(total):6.1f} ms  "
      f"tracked per frame {per_frame:4.2f}  per tracked object "
      f"{(mo / per_frame) if per_frame > 0 else 0:5.1f} ms  lost {s['lost']}/{s['frames']}")
PY
}

for n in 1 3 5; do
  seq="$out/cars_$n"
  [ -f "$seq/associations.txt" ] || "$bin/df_make_sequence" --preset "cars_$n" --out "$seq" \
    --frames "$frames" >/dev/null
  for objects in on off; do
    dir="$out/run_cars_${n}_$objects"
    rm -rf "$dir"
    "$bin/df_slam" offline "$seq" -o "$dir" --masks "$seq/instances" \
      --set "slam { objects { enabled: $([ $objects = on ] && echo true || echo false) } }" \
      >"$dir.log" 2>&1
    report "cars_$n objects $objects" "$dir"
  done
done
