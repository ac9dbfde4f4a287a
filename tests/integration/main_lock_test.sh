#!/usr/bin/env bash
# deploy/main.sh checks first and deletes later: a second main.sh on the same DF_OUT refuses at
# once, naming the first, before set-up, build or any delete; Ctrl-C prints one line. Runs a copy
# of main.sh whose set-up and build are stand-ins that leave a mark (nothing is installed/built).
source "$(dirname "$0")/lib.sh"
fake="$TMP/root"
mkdir -p "$fake/deploy" "$TMP/out/slam"
cp "$SRC/deploy/main.sh" "$fake/deploy/main.sh"
for f in dfsup dfsup_watch.py pipeline.proto; do ln -s "$SRC/deploy/$f" "$fake/deploy/$f"; done
printf 'echo setup >> "%s/marks"; sleep "${FAKE_SETUP_S:-0}"\n' "$TMP" > "$fake/deploy/setup.sh"
printf 'echo build >> "%s/marks"\n' "$TMP" > "$fake/deploy/build.sh"
echo "first run's pose" > "$TMP/out/slam/trajectory.txt"

# The first main.sh holds the lock (a stand-in that holds it the same way).
bash -c 'exec 9>>"$1"; flock 9; exec sleep 60' _ "$TMP/out/.main.lock" &
holder=$!
pids+=("$holder")
echo "$holder" > "$TMP/out/.main.pid"
for _ in $(seq 50); do flock -n "$TMP/out/.main.lock" true || break; sleep 0.1; done
if out=$(DF_OUT="$TMP/out" timeout 30 bash "$fake/deploy/main.sh" 2>&1); then
  fail "a second main.sh ran: $out"
fi
[[ "$out" == *"pid $holder"* ]] || fail "the refusal does not name the running main.sh (pid $holder): $out"
[ ! -e "$TMP/marks" ] || fail "the refused main.sh ran $(cat "$TMP/marks")"
[ "$(cat "$TMP/out/slam/trajectory.txt")" = "first run's pose" ] || fail "the first run's output changed"
pass "second main.sh refused: $out"
kill "$holder" 2>/dev/null || true
wait "$holder" 2>/dev/null || true

# Ctrl-C (SIGINT to the process group, as a terminal sends it) while it sets up: one line.
# (dfsup check is a stand-in here: a RouDi of another test may run on this machine.)
rm "$fake/deploy/dfsup"
printf '#!/bin/sh\nexit 0\n' > "$fake/deploy/dfsup"
chmod +x "$fake/deploy/dfsup"
set -m
FAKE_SETUP_S=30 DF_OUT="$TMP/out" bash "$fake/deploy/main.sh" >"$TMP/int.out" 2>&1 &
job=$!
set +m
for _ in $(seq 100); do [ -e "$TMP/marks" ] && break; sleep 0.1; done
[ -e "$TMP/marks" ] || fail "main.sh never reached set-up: $(cat "$TMP/int.out")"
kill -INT -- "-$job"
rc=0
wait "$job" || rc=$?
[ "$rc" = 130 ] || fail "main.sh exited $rc after Ctrl-C, expected 130: $(cat "$TMP/int.out")"
grep -q Traceback "$TMP/int.out" && fail "Ctrl-C printed a traceback: $(cat "$TMP/int.out")"
[ "$(wc -l < "$TMP/int.out")" = 1 ] || fail "Ctrl-C printed more than one line: $(cat "$TMP/int.out")"
pass "Ctrl-C: $(cat "$TMP/int.out")"
exit 0
