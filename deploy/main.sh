#!/usr/bin/env bash
# README command (a): set up, build, and run the main job on the built-in default data.
# For now (until the SLAM service exists) the main job plays the default sequence through the
# capture service over shared memory into an MCAP recording, under the supervisor, and prints
# what arrived (frames, rate, latency).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if [ "$(id -u)" -eq 0 ]; then bash deploy/setup.sh; else sudo bash deploy/setup.sh; fi
bash deploy/build.sh
export DF_OUT="${DF_OUT:-$root/out/main}"
run_dir="$DF_OUT/run"
rm -f "$DF_OUT/frames.mcap"
deploy/dfsup --run-dir "$run_dir" up deploy/pipelines/record_default.pbtxt
trap 'deploy/dfsup --run-dir "$run_dir" down >/dev/null 2>&1 || true' EXIT
status=0
deploy/dfsup --run-dir "$run_dir" wait recorder --timeout 300 || status=$?
echo
echo "== what arrived =="
grep -E "^(recorded|  )" "$run_dir/logs/recorder.log" || true
grep -E "done:|bad frame" "$run_dir/logs/capture.log" | sed 's/^[^]]*\] //' || true
echo
echo "recording: $DF_OUT/frames.mcap (open it in Foxglove Studio, or: build/bin/df_tap play $DF_OUT/frames.mcap)"
echo "logs:      $run_dir/logs/"
exit $status
