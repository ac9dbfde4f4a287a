#!/usr/bin/env bash
# The whole pipeline live on this machine: SLAM, geometric segmentation, YOLOv5s at 320x320 and
# fusion under the supervisor (dfsup, which also starts RouDi), fed by capture at the sequence's
# 30 Hz (REALTIME, the default sequence twice) over shared memory; detection on every frame, on
# every third frame, and stopped. Prints per mode: the rate
# of object_segments and camera_pose, the latency from capture to object_segments (df_tap delay),
# and how many frames fusion published with their own, reused or no detections.
# Usage: tests/bench/run_pipeline_bench.sh [SEQUENCE] (default build/data/default);
# DF_BENCH_MODES="full third stopped" picks modes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$root/build/bin"
seq="${1:-$root/build/data/default}"
out="$(mktemp -d /tmp/df_pipeline_bench.XXXXXX)"
sup="$root/deploy/dfsup --run-dir $out/run"
trap '$sup down >/dev/null 2>&1 || true' EXIT
run_mode() {  # name every_nth (0 = no detector)
  local name=$1 nth=$2 ns="bench_$1_$$" pids=()
  {
    echo "name: \"bench-$name\""
    echo 'service { name: "slam" binary: "df_slam" args: ["run", "--set", "dds { ns: \"${DF_NS}\" }"] }'
    echo 'service { name: "geoseg" binary: "df_geoseg" args: ["--set", "dds { ns: \"${DF_NS}\" }"] }'
    [ "$nth" -gt 0 ] && echo "service { name: \"detector\" binary: \"df_detector\" config: \"deploy/config/detector_default.pbtxt\" args: [\"--set\", \"dds { ns: \\\"\${DF_NS}\\\" }\", \"--set\", \"every_nth: $nth\"] }"
    echo 'service { name: "fusion" binary: "df_fusion" args: ["--set", "dds { ns: \"${DF_NS}\" }"] }'
  } >"$out/$name.pbtxt"
  $sup up "$out/$name.pbtxt" --var "DF_NS=$ns" >/dev/null
  "$bin/df_tap" delay "$ns/object_segments" --idle 3 >"$out/$name.delay" 2>&1 & pids+=($!)
  "$bin/df_tap" hz "$ns/object_segments" --idle 3 >"$out/$name.hz" 2>&1 & pids+=($!)
  "$bin/df_tap" hz "$ns/camera_pose" --idle 3 >"$out/$name.pose_hz" 2>&1 & pids+=($!)
  sleep 6  # supervisor start, discovery, model load
  "$bin/df_capture" "$seq" --config "$root/deploy/config/capture_realtime.pbtxt" \
    --set "dds { ns: \"$ns\" }" --set "loops: 2" >"$out/$name.capture.log" 2>&1
  for p in "${pids[@]}"; do wait "$p" || true; done
  $sup wait fusion --timeout 30 >/dev/null || true
  for s in slam geoseg detector fusion; do
    [ -f "$out/run/logs/$s.log" ] && cp "$out/run/logs/$s.log" "$out/$name.$s.log"
  done
  $sup down >/dev/null
  echo "== detection: $name"
  grep -h "average rate" "$out/$name.hz" | tail -1 | sed 's/^/object_segments: /'
  grep -h "average rate" "$out/$name.pose_hz" | tail -1 | sed 's/^/camera_pose:     /'
  grep -hiE "delay|median|p95" "$out/$name.delay" | tail -2 | sed 's/^/capture -> object_segments: /'
  grep -h "stream ended" "$out/$name.fusion.log" | sed 's/^.*\] //'
  [ "$nth" -gt 0 ] && grep -h "stream ended" "$out/$name.detector.log" | sed 's/^.*\] //'
  return 0
}
echo "pipeline bench on $(nproc) cores; logs in $out"
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *full* ]]; then run_mode full 1; fi
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *third* ]]; then run_mode third 3; fi
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *stopped* ]]; then run_mode stopped 0; fi
