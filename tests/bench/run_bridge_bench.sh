#!/usr/bin/env bash
# What `df_tap bridge` costs the pipeline: capture at the sequence's 30 Hz (REALTIME) into the
# segmentation services (SIMULATED detector) and SLAM over shared memory, three times: without
# a bridge; with the bridge at its defaults and a Foxglove client (@foxglove/ws-protocol) reading
# every channel; with the bridge and a client that subscribes to everything and stops reading.
# Prints per case the camera_pose rate and its delay from capture (df_tap), the bridge's CPU per
# second, and what the client received per channel (messages/s, MB/s) or the bridge dropped.
# Usage: tests/bench/run_bridge_bench.sh [SEQUENCE] (default build/data/default); DF_BENCH_S
# seconds per case (default 20); DF_BENCH_BRIDGE_ARGS extra bridge options (e.g. "--jpeg 0").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="$root/build/bin"
seq="${1:-$root/build/data/default}"
secs="${DF_BENCH_S:-20}"
out="$(mktemp -d /tmp/df_bridge_bench.XXXXXX)"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
if ! { [ -e /tmp/roudi.lock ] && ! flock -n /tmp/roudi.lock true; }; then
  iox-roudi -c "$root/deploy/config/roudi.toml" -l warning >"$out/roudi.log" 2>&1 &
  pids+=($!)
  sleep 1
fi
ticks=$(getconf CLK_TCK)
cpu_ticks() { local f; read -r -a f <<<"$(sed 's/^.*) //' "/proc/$1/stat")"; echo $((f[11] + f[12])); }

run_case() {  # name: none | reading | stalled
  local name=$1 ns="bb_$1_$$" case_pids=()
  "$bin/df_geoseg" --set "dds { ns: \"$ns\" }" >"$out/$name.geoseg.log" 2>&1 & case_pids+=($!)
  "$bin/df_detector" --set "dds { ns: \"$ns\" }" --set 'model: "simulated"' \
    --set "sim_sequence: \"$seq\"" >"$out/$name.detector.log" 2>&1 & case_pids+=($!)
  "$bin/df_fusion" --set "dds { ns: \"$ns\" }" >"$out/$name.fusion.log" 2>&1 & case_pids+=($!)
  "$bin/df_slam" run --set "dds { ns: \"$ns\" }" --set "output { dir: \"$out/$name.slam\" log_every: 0 }" \
    --set 'segments_deadline_ms: 40' --set 'exit_at_end: false' >"$out/$name.slam.log" 2>&1 & case_pids+=($!)
  local bridge="" port=""
  if [ "$name" != none ]; then
    # shellcheck disable=SC2086
    : >"$out/$name.bridge.out"
    "$bin/df_tap" bridge --ns "$ns" --port 0 ${DF_BENCH_BRIDGE_ARGS:-} >"$out/$name.bridge.out" 2>"$out/$name.bridge.log" &
    bridge=$!; case_pids+=($bridge)
    for _ in $(seq 100); do
      port=$(sed -n 's|^bridge: ws://127.0.0.1:\([0-9]*\) .*|\1|p' "$out/$name.bridge.out"); [ -n "$port" ] && break; sleep 0.1
    done
    local flag=""; [ "$name" = stalled ] && flag=--stall
    node "$root/tests/js/bridge_watch.mjs" "ws://127.0.0.1:$port" "$((secs + 2))" $flag >"$out/$name.client.json" &
    case_pids+=($!)
  fi
  "$bin/df_tap" hz "$ns/camera_pose" --duration "$secs" >"$out/$name.hz" 2>&1 & local hz=$!
  "$bin/df_tap" delay "$ns/camera_pose" --duration "$secs" >"$out/$name.delay" 2>&1 & local dl=$!
  sleep 3
  "$bin/df_capture" "$seq" --config "$root/deploy/config/capture_realtime.pbtxt" \
    --set "dds { ns: \"$ns\" }" --set 'loops: 100' >"$out/$name.capture.log" 2>&1 & case_pids+=($!)
  local c0=0 c1=0
  sleep 1
  [ -n "$bridge" ] && c0=$(cpu_ticks "$bridge")
  wait $hz $dl || true
  [ -n "$bridge" ] && c1=$(cpu_ticks "$bridge")
  sleep 2
  for p in "${case_pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${case_pids[@]}"; do wait "$p" 2>/dev/null || true; done
  echo "== $name"
  grep -h "average rate" "$out/$name.hz" | tail -1 | sed 's/^/camera_pose: /'
  grep -hE "p50|median" "$out/$name.delay" | tail -1 | sed 's/^/capture -> camera_pose: /'
  if [ -n "$bridge" ]; then
    awk -v a="$c0" -v b="$c1" -v t="$ticks" -v s="$secs" 'BEGIN { printf "bridge CPU: %.1f %% of one core\n", 100 * (b - a) / t / (s - 1) }'
    grep -hE "dropped" "$out/$name.bridge.log" | tail -3 | sed 's/^[^]]*\] /bridge: /'
    /usr/bin/python3 - "$out/$name.client.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
if d.get("stalled"):
    print("client: stalled (stopped reading after 0.5 s)")
else:
    for t, c in sorted(d["channels"].items()):
        print(f"client {t}: {c['messages'] / d['seconds']:.1f} msg/s, {c['bytes'] / d['seconds'] / 1e6:.2f} MB/s")
PY
  fi
}
for c in ${DF_BENCH_CASES:-none reading stalled}; do run_case "$c"; done
echo "(logs in $out)"
