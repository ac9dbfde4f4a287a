#!/usr/bin/env bash
# CTest fixture: 'start' runs an iceoryx RouDi for the shared-memory tests unless one runs;
# 'stop' stops it only if 'start' started it. RouDi must outlive the test processes: at
# shutdown it sends SIGTERM to every process still registered with it.
set -euo pipefail
cmd="$1"; conf="$2"; state="$3"
running() { [ -e /tmp/roudi.lock ] && ! flock -n /tmp/roudi.lock true; }
case "$cmd" in
  start)
    if running; then echo "RouDi already running; using it"; rm -f "$state"; exit 0; fi
    setsid iox-roudi -c "$conf" -l warning > "$state.log" 2>&1 < /dev/null &
    echo $! > "$state"
    for _ in $(seq 100); do running && { echo "RouDi started (pid $(cat "$state"))"; exit 0; }; sleep 0.1; done
    echo "RouDi did not start: $(cat "$state.log")" >&2; exit 1 ;;
  stop)
    [ -f "$state" ] || { echo "RouDi not started by the tests; left running"; exit 0; }
    pid=$(cat "$state"); kill -INT "$pid" 2>/dev/null || true
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || { rm -f "$state"; echo "RouDi stopped"; exit 0; }; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true; rm -f "$state"; echo "RouDi killed" ;;
esac
