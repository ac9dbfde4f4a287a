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
# DF_BENCH_MODES="full third stopped" picks modes, DF_BENCH_LOOPS the times the sequence plays
# (default 2; 1 for the camera ATE against a generated sequence's ground truth).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$root/build/bin"
seq="${1:-$root/build/data/default}"
deadline="${DF_BENCH_DEADLINE_MS:-40}"
loops="${DF_BENCH_LOOPS:-2}"
out="$(mktemp -d /tmp/df_pipeline_bench.XXXXXX)"
sup="$root/deploy/dfsup --run-dir $out/run"
trap '$sup down >/dev/null 2>&1 || true' EXIT
ticks=$(getconf CLK_TCK)
sample() {  # "comm pid cpu_ticks threads" per pid given; only shell builtins (no fork)
  local p line f comm
  for p in "$@"; do
    read -r line 2>/dev/null <"/proc/$p/stat" || continue
    comm=${line#*(}; comm=${comm%%)*}
    read -r -a f <<<"${line##*) }"
    echo "$comm $p $((f[11] + f[12])) ${f[17]}"
  done
}
run_mode() {  # name every_nth (0 = no detector)
  local name=$1 nth=$2 ns="bench_$1_$$" pids=()
  {
    echo "name: \"bench-$name\""
    echo "service { name: \"slam\" binary: \"df_slam\" args: [\"run\", \"--set\", \"dds { ns: \\\"\${DF_NS}\\\" }\", \"--set\", \"segments_deadline_ms: $deadline\", \"--set\", \"output { log_every: 0 dir: \\\"$out/$name.slam\\\" }\"] }"
    echo 'service { name: "geoseg" binary: "df_geoseg" args: ["--set", "dds { ns: \"${DF_NS}\" }"] }'
    [ "$nth" -gt 0 ] && echo "service { name: \"detector\" binary: \"df_detector\" config: \"deploy/config/detector_default.pbtxt\" nice: ${DF_BENCH_DETECTOR_NICE:-10} args: [\"--set\", \"dds { ns: \\\"\${DF_NS}\\\" }\", \"--set\", \"every_nth: $nth\"] }"
    echo 'service { name: "fusion" binary: "df_fusion" args: ["--set", "dds { ns: \"${DF_NS}\" }", "--set", "republish_late_ms: 1000"] }'
  } >"$out/$name.pbtxt"
  $sup up "$out/$name.pbtxt" --var "DF_NS=$ns" >/dev/null
  "$bin/df_tap" delay "$ns/object_segments" --idle 3 >"$out/$name.delay" 2>&1 & pids+=($!)
  "$bin/df_tap" delay "$ns/camera_pose" --idle 3 >"$out/$name.pose_delay" 2>&1 & pids+=($!)
  "$bin/df_tap" hz "$ns/object_segments" --idle 3 >"$out/$name.hz" 2>&1 & pids+=($!)
  "$bin/df_tap" hz "$ns/camera_pose" --idle 3 >"$out/$name.pose_hz" 2>&1 & pids+=($!)
  sleep 6  # supervisor start, discovery, model load
  "$bin/df_capture" "$seq" --config "$root/deploy/config/capture_realtime.pbtxt" \
    --set "dds { ns: \"$ns\" }" --set "loops: $loops" >"$out/$name.capture.log" 2>&1 &
  local capture=$! t0 t1 stat0 stat1 procs
  procs=($(pgrep -f -- "$ns" || true) $(pgrep -x iox-roudi || true))
  sample "${procs[@]}" >"$out/$name.cpu0"
  stat0=$(head -1 /proc/stat)
  t0=$(date +%s.%N)
  # The services exit at the stream's end: sample every 0.2 s, keep each one's last sample.
  ( while :; do sample "${procs[@]}" >>"$out/$name.cpu_samples"; sleep 0.2; done ) &
  local sampler=$!
  wait "$capture" || true
  t1=$(date +%s.%N)
  stat1=$(head -1 /proc/stat)
  kill "$sampler" 2>/dev/null || true
  wait "$sampler" 2>/dev/null || true
  # Each process's last sample (the most CPU time it reached), its thread count at its peak.
  awk '$3 >= t[$2] { t[$2] = $3; line[$2] = $0 } END { for (p in line) print line[p] }' \
    "$out/$name.cpu_samples" >"$out/$name.cpu1"
  for p in "${pids[@]}"; do wait "$p" || true; done
  $sup wait fusion --timeout 30 >/dev/null || true
  $sup wait slam --timeout 60 >/dev/null || true
  for s in slam geoseg detector fusion; do
    [ -f "$out/run/logs/$s.log" ] && cp "$out/run/logs/$s.log" "$out/$name.$s.log"
  done
  $sup down >/dev/null
  local frames
  frames=$(grep -hoE "done: [0-9]+ frames published" "$out/$name.capture.log" | grep -oE "[0-9]+" | head -1)
  echo "== detection: $name (SLAM segments deadline $deadline ms; $frames frames captured in $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s)"
  grep -h "average rate" "$out/$name.hz" | tail -1 | sed 's/^/object_segments: /'
  grep -h "average rate" "$out/$name.pose_hz" | tail -1 | sed 's/^/camera_pose:     /'
  grep -hiE "delay|median|p95|p99" "$out/$name.delay" | tail -2 | sed 's/^/capture -> object_segments: /'
  grep -hiE "delay|median|p95|p99" "$out/$name.pose_delay" | tail -2 | sed 's/^/capture -> camera_pose: /'
  grep -h "stream ended" "$out/$name.fusion.log" | sed 's/^.*\] //' || true
  if [ "$nth" -gt 0 ]; then grep -h "stream ended" "$out/$name.detector.log" | sed 's/^.*\] //' || true; fi
  grep -h "stream ended" "$out/$name.slam.log" | sed 's/^.*\] /slam: /' || true
  if [ -f "$seq/groundtruth.txt" ] && [ -f "$out/$name.slam/trajectory.txt" ]; then
    "$bin/df_eval" ate "$seq/groundtruth.txt" "$out/$name.slam/trajectory.txt" 2>/dev/null |
      grep -m1 "ATE translation" | sed 's/^ */camera ATE of the tracked frames (rmse mean median ...): /' || true
  fi
  # The machine as a whole over the capture: busy, idle and stolen (a virtual machine's host).
  echo "$stat0 $stat1" | awk '{ n = (NF - 2) / 2; for (i = 2; i <= n + 1; ++i) d[i - 1] = $(i + n + 1) - $i;
    busy = d[1] + d[2] + d[3] + d[6] + d[7]; total = busy + d[4] + d[5] + d[8];
    printf "machine: %.0f %% busy, %.0f %% idle, %.0f %% stolen by the host (of %d cores)\n",
           100 * busy / total, 100 * (d[4] + d[5]) / total, 100 * d[8] / total, '"$(nproc)"' }'
  awk -v ticks="$ticks" -v frames="${frames:-0}" -v wall="$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')" '
    NR == FNR { start[$2] = $3; next }
    { ms = ($3 - start[$2]) * 1000 / ticks; total[$1] += ms; threads[$1] += $4 }
    END { for (c in total)
            printf "cpu %-12s %7.1f ms per frame, %5.1f %% of a core, %s threads\n", c,
                   (frames > 0 ? total[c] / frames : 0), 100 * total[c] / 1000 / wall, threads[c] }' \
    "$out/$name.cpu0" "$out/$name.cpu1" | sort -k3 -n -r
  return 0
}
echo "pipeline bench on $(nproc) cores, $(basename "$seq"); logs in $out"
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *full* ]]; then run_mode full 1; fi
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *third* ]]; then run_mode third 3; fi
if [ -z "${DF_BENCH_MODES:-}" ] || [[ "$DF_BENCH_MODES" == *stopped* ]]; then run_mode stopped 0; fi
