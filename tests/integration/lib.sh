# Shared helpers of the shell integration tests.
set -euo pipefail
BIN="${DF_TEST_BIN:?}"; SRC="${DF_TEST_SRC:?}"
TMP="$(mktemp -d "${TMPDIR:-/tmp}/dftest-XXXXXX")"
NS="t$$_${RANDOM}"
pids=()
cleanup() {
  for p in "${pids[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  [ -n "${DF_KEEP_TEST_FILES:-}" ] || rm -rf "$TMP"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
pass() { echo "ok: $*"; }
roudi_running() { [ -e /tmp/roudi.lock ] && ! flock -n /tmp/roudi.lock true; }

# --- Tests that run a pipeline under dfsup (their own RouDi, so none may run already).
# Exits 77 (CTest's skip) when a RouDi runs on this machine.
need_own_roudi() {
  if roudi_running; then
    echo "SKIP: a RouDi is already running on this machine; this test needs to start its own under dfsup"
    exit 77
  fi
}
# A generated sequence: make_sequence FRAMES [df_make_sequence options...] writes $TMP/seq.
make_sequence() {
  local frames="$1"; shift
  "$BIN/df_make_sequence" --preset default --out "$TMP/seq" --frames "$frames" "$@" >/dev/null 2>&1 \
    || fail "df_make_sequence failed"
}
# The pipeline file's capture service: the test's sequence at its own rate, on the test's namespace.
capture_service() {
  cat <<PB
service {
  name: "capture"
  binary: "df_capture"
  config: "deploy/config/capture_realtime.pbtxt"
  args: ["\${DF_DATA}", "--set", "dds { ns: \"\${DF_NS}\" }"]
}
PB
}
# sup_up PIPELINE [RUN_DIR]: dfsup up with run dir RUN_DIR (default $TMP/run) and the test's
# sequence, namespace, output folder and build; sets RUN and SUP, and brings the pipeline down
# when the test exits.
sup_up() {
  RUN="${2:-$TMP/run}"
  SUP="$SRC/deploy/dfsup --run-dir $RUN"
  $SUP up "$1" --var "DF_DATA=$TMP/seq" --var "DF_NS=$NS" --var "DF_OUT=$TMP/out" \
    --var "DF_BUILD=$(dirname "$BIN")"
  trap '$SUP down >/dev/null 2>&1 || true; cleanup' EXIT
}
# dfsup down (a failure fails the test); the exit trap no longer brings the pipeline down.
sup_down() {
  $SUP down || fail "dfsup down exited with $?"
  trap cleanup EXIT
}
# sup_kill_restarted SERVICE: SIGKILLs the service's process and waits (10 s at most) until the
# supervisor runs it again under a new pid; sets killed_pid and new_pid, fails the test otherwise.
sup_kill_restarted() {
  killed_pid=$($SUP status | awk -v s="$1" '$1==s {print $4}')
  [ -n "$killed_pid" ] && [ "$killed_pid" != 0 ] || fail "no $1 running: $($SUP status)"
  kill -KILL "$killed_pid"
  new_pid=
  for _ in $(seq 200); do
    new_pid=$($SUP status | awk -v s="$1" '$1==s && $2=="RUNNING" {print $4}')
    [ -n "$new_pid" ] && [ "$new_pid" != "$killed_pid" ] && return 0
    sleep 0.05
  done
  fail "$1 was not restarted after kill -9 of pid $killed_pid ($($SUP status))"
}
# start_segmentation SEQ: df_geoseg, the SIMULATED df_detector on SEQ's ground truth and
# df_fusion in the background on the test's namespace (logs in $TMP/<service>.log).
start_segmentation() {
  "$BIN/df_geoseg" --set "dds { ns: \"$NS\" }" >"$TMP/geoseg.log" 2>&1 &
  pids+=($!)
  "$BIN/df_detector" --set "dds { ns: \"$NS\" }" --set 'model: "simulated"' \
    --set "sim_sequence: \"$1\"" >"$TMP/detector.log" 2>&1 &
  pids+=($!)
  "$BIN/df_fusion" --set "dds { ns: \"$NS\" }" >"$TMP/fusion.log" 2>&1 &
  pids+=($!)
}
# capture_lockstep SEQ STAGE...: plays SEQ to the end, each frame after every STAGE answered it
# (60 s at most per frame; 30 s for the stages' readers to appear); fails the test if it fails.
capture_lockstep() {
  local seq="$1"; shift
  local stages=()
  for s in "$@"; do stages+=(--set "lockstep_stages: \"$s\""); done
  "$BIN/df_capture" "$seq" --set "dds { ns: \"$NS\" }" --set 'playback: LOCKSTEP' "${stages[@]}" \
    --set 'start_wait_s: 30' --set 'lockstep_timeout_s: 60' >"$TMP/capture.log" 2>&1 \
    || fail "capture failed: $(tail -3 "$TMP/capture.log")"
}
