#!/usr/bin/env bash
# The whole pipeline live on this machine: dynamic SLAM with object maps, geometric
# segmentation, YOLOv5s (deploy/config/detector_default.pbtxt) and fusion under the supervisor
# (dfsup, which also starts RouDi), fed by capture at the sequence's 30 Hz (REALTIME, the
# sequence twice) over shared memory; detection on every frame the detector can take (it stays
# current), on every third frame at most, and stopped. SLAM waits DF_BENCH_DEADLINE_MS (default
# 40) for a frame's segments, then tracks with what it has: the newest instances, carried
# forward (object segments that arrive after their frame was tracked are carried too).
# Prints per mode: the rates of object_segments and camera_pose, the latency from capture to
# object_segments and to camera_pose (df_tap delay), how many frames fusion published with
# their own, reused or no detections, what SLAM tracked past the deadline and carried, and
# per process the CPU time per captured frame and the thread count (from /proc).
# Usage: tests/bench/run_pipeline_bench.sh [SEQUENCE] (default build/data/default);
# DF_BENCH_MODES="full third stopped" picks modes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$root/build/bin"
seq="${1:-$root/build/data/default}"
deadline="${DF_BENCH_DEADLINE_MS:-40}"
out="$(mktemp -d /tmp/df_pipeline_bench.XXXXXX)"
sup="$root/deploy/dfsup --run-dir $out/run"
trap '$sup down >/dev/null 2>&1 || true' EXIT
ticks=$(getconf CLK_TCK)
cpu_of() {  # "comm cpu_ticks threads" of every process whose command line names namespace $1
  local p f
  for p in $(pgrep -f -- "$1"); do
    [ -r "/proc/$p/stat" ] || continue
    read -r -a f < <(sed 's/^.*) //' "/proc/$p/stat") || continue
    echo "$(cat "/proc/$p/comm" 2>/dev/null) $((f[11] + f[12])) ${f[17]}"
  done
}
run_mode() {  # name every_nth (0 = no detector)
  local name=$1 nth=$2 ns="bench_$1_$$" pids=()
  {
    echo "name: \"bench-$name\""
    echo "service { name: \"slam\" binary: \"df_slam\" args: [\"run\", \"--set\", \"dds { ns: \\\"\${DF_NS}\\\" }\", \"--set\", \"segments_deadline_ms: $deadline\", \"--set\", \"output { log_every: 0 }\"] }"
    echo 'service { name: "geoseg" binary: "df_geoseg" args: ["--set", "dds { ns: \"${DF_NS}\" }"] }'
    [ "$nth" -gt 0 ] && echo "service { name: \"detector\" binary: \"df_detector\" config: \"deploy/config/detector_default.pbtxt\" args: [\"--set\", \"dds { ns: \\\"\${DF_NS}\\\" }\", \"--set\", \"every_nth: $nth\"] }"
    echo 'service { name: "fusion" binary: "df_fusion" args: ["--set", "dds { ns: \"${DF_NS}\" }"] }'
  } >"$out/$name.pbtxt"
  $sup up "$out/$name.pbtxt" --var "DF_NS=$ns" >/dev/null
  "$bin/df_tap" delay "$ns/object_segments" --idle 3 >"$out/$name.delay" 2>&1 & pids+=($!)
  "$bin/df_tap" delay "$ns/camera_pose" --idle 3 >"$out/$name.pose_delay" 2>&1 & pids+=($!)
  "$bin/df_tap" hz "$ns/object_segments" --idle 3 >"$out/$name.hz" 2>&1 & pids+=($!)
  "$bin/df_tap" hz "$ns/camera_pose" --idle 3 >"$out/$name.pose_hz" 2>&1 & pids+=($!)
  sleep 6  # supervisor start, discovery, model load
  cpu_of "$ns" | grep -v df_tap >"$out/$name.cpu0" || true
  local t0 t1
  t0=$(date +%s.%N)
  "$bin/df_capture" "$seq" --config "$root/deploy/config/capture_realtime.pbtxt" \
    --set "dds { ns: \"$ns\" }" --set "loops: 2" >"$out/$name.capture.log" 2>&1
  t1=$(date +%s.%N)
  cpu_of "$ns" | grep -v df_tap >"$out/$name.cpu1" || true
  for p in "${pids[@]}"; do wait "$p" || true; done
  $sup wait fusion --timeout 30 >/dev/null || true
  $sup wait slam --timeout 60 >/dev/null || true
  for s in slam geoseg detector fusion; do
    [ -f "$out/run/logs/$s.log" ] && cp "$out/run/logs/$s.log" "$out/$name.$s.log"
  done
  $sup down >/dev/null
  local frames
  frames=$(grep -hoE "published [0-9]+ frames|[0-9]+ frames (published|sent)" "$out/$name.capture.log" | grep -oE "[0-9]+" | tail -1)
  echo "== detection: $name (SLAM segments deadline $deadline ms; $frames frames captured in $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s)"
  grep -h "average rate" "$out/$name.hz" | tail -1 | sed 's/^/object_segments: /'
  grep -h "average rate" "$out/$name.pose_hz" | tail -1 | sed 's/^/camera_pose:     /'
  grep -hiE "delay|median|p95|p99" "$out/$name.delay" | tail -2 | sed 's/^/capture -> object_segments: /'
  grep -hiE "delay|median|p95|p99" "$out/$name.pose_delay" | tail -2 | sed 's/^/capture -> camera_pose: /'
  grep -h "stream ended" "$out/$name.fusion.log" | sed 's/^.*\] //'
  [ "$nth" -gt 0 ] && grep -h "stream ended" "$out/$name.detector.log" | sed 's/^.*\] //'
  grep -h "stream ended" "$out/$name.slam.log" | sed 's/^.*\] /slam: /'
  awk -v ticks="$ticks" -v frames="${frames:-0}" -v wall="$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')" '
    NR == FNR { start[$1] = $2; next }
    { ms = ($2 - start[$1]) * 1000 / ticks;
      printf "cpu %-12s %7.1f ms per frame, %5.1f %% of a core, %s threads\n", $1,
             frames > 0 ? ms / frames : 0, 100 * ms / 1000 / wall, $3 }' \
    "$out/$name.cpu0" "$out/$name.cpu1"
  return 0
}
echo "pipeline bench on $(nproc) cores, $(basename "$seq"); logs in $out"
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *full* ]]; then run_mode full 1; fi
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *third* ]]; then run_mode third 3; fi
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *stopped* ]]; then run_mode stopped 0; fi
