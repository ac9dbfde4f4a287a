#!/usr/bin/env bash
# A pipeline that heals, under dfsup: capture -> geoseg over shared memory with df_health and the
# watcher. RouDi SIGKILLed -> healed, frames flow again; RouDi SIGSTOPped (alive, not serving, as
# in iceoryx's deadlock) -> found stuck, healed, frames flow again; df_health SIGSTOPped -> its
# status goes stale, healed; a detector whose model is
# missing goes FATAL with its reason in `dfsup status`; a second `dfsup up` refuses, naming the
# first run, and touches none of its files; `dfsup down` leaves no process and no RouDi.
source "$(dirname "$0")/lib.sh"
need_own_roudi
make_sequence 30
cat > "$TMP/pipeline.pbtxt" <<PB
name: "heal-test"
service {
  name: "geoseg"
  binary: "df_geoseg"
  args: ["--set", "dds { ns: \"\${DF_NS}\" }"]
  priority: 50
}
service {
  name: "detector"
  binary: "df_detector"
  args: ["--set", "dds { ns: \"\${DF_NS}\" }", "--set", "model_path: \"$TMP/no-such-model\""]
  priority: 50
}
service {
  name: "slowrefuse"
  binary: "$TMP/slow_refuse.sh"
  priority: 50
}
$(capture_service)
PB
# A service that refuses its configuration only after START_S (as a loaded machine makes any
# service do): exit status 2 must still end in FATAL, not in restarts for ever.
printf '#!/bin/sh\necho "[error] slowrefuse: no such calibration (made up)"\nsleep 2\nexit 2\n' \
  > "$TMP/slow_refuse.sh"
chmod +x "$TMP/slow_refuse.sh"
sup_up "$TMP/pipeline.pbtxt"

# geoseg's answers: "<answers> <age_s>" from df_health's file (empty when none yet).
answers() {
  /usr/bin/python3 - "$RUN/health.json" <<'PY' 2>/dev/null || true
import json, sys, time, os
p = sys.argv[1]
j = json.load(open(p))
a = j["stages"].get("geoseg")
if a:
    print(a["answers"], a["age_s"] + time.time() - os.path.getmtime(p), j["pid"])
PY
}
# Waits (up to 60 s) until geoseg answers newer than "$1" answers of health pid "$2" arrive.
wait_flowing() {
  local since_pid="$2" a
  for _ in $(seq 600); do
    a=$(answers)
    if [ -n "$a" ]; then
      read -r n age pid <<<"$a"
      if [ "$pid" != "$since_pid" ] || [ "$n" -gt "$1" ]; then
        awk -v g="$age" 'BEGIN { exit !(g < 1.0) }' && return 0
      fi
    fi
    sleep 0.1
  done
  return 1
}
wait_flowing 0 none || fail "frames never flowed to geoseg: $($SUP status)"
status=$($SUP status)
grep -E "^geoseg .*frames: flowing" <<<"$status" >/dev/null || fail "status shows no flow: $status"
grep -E "^roudi .*health: ok" <<<"$status" >/dev/null || fail "status shows no RouDi health: $status"
pass "frames flow; status: $(grep ^geoseg <<<"$status" | sed 's/  */ /g')"

# A missing model: FATAL after a few tries, with its reason.
for _ in $(seq 300); do $SUP status | grep -q "^detector .*FATAL" && break; sleep 0.1; done
line=$($SUP status | grep "^detector" || true)
[[ "$line" == *FATAL* ]] || fail "detector with a missing model is not FATAL: $line"
[[ "$line" == *"no-such-model"* ]] || fail "FATAL detector shows no reason naming the model: $line"
starts=$(grep -c "spawned: 'detector'" "$RUN/supervisord.log")
[ "$starts" -le 5 ] || fail "detector was started $starts times before FATAL"
pass "detector FATAL after $starts starts: ${line#*last error: }"
for _ in $(seq 100); do $SUP status | grep -q "^slowrefuse .*FATAL" && break; sleep 0.1; done
line=$($SUP status | grep "^slowrefuse" || true)
[[ "$line" == *FATAL*"no such calibration"* ]] || fail "a service refusing after 2 s is not FATAL with its reason: $line"
starts=$(grep -c "spawned: 'slowrefuse'" "$RUN/supervisord.log")
[ "$starts" -eq 1 ] || fail "a service refusing its configuration after 2 s was started $starts times"
pass "a slow refusal is FATAL after one start: ${line#*last error: }"
# Waiting for another service while one can never start stops at once, naming it (main.sh waits
# for slam: a FATAL capture or detector must not leave it waiting for frames for 15 minutes).
rc=0; out=$($SUP wait geoseg --timeout 60 2>&1) || rc=$?
[ "$rc" -eq 4 ] || fail "dfsup wait geoseg with a FATAL detector returned $rc, expected 4: $out"
[[ "$out" == *"detector cannot start"*"no-such-model"* ]] || fail "dfsup wait names no FATAL service: $out"
pass "dfsup wait stops at a FATAL service: $(tail -1 <<<"$out")"

heal_round() {  # signal, expected reason in heal.log, program to signal (default roudi)
  local before n pid roudi victim
  before=$(grep -c "; started" "$RUN/heal.log" 2>/dev/null || true)
  read -r n _ pid <<<"$(answers)"
  roudi=$($SUP status | awk '$1=="roudi" {print $4}')
  victim=$($SUP status | awk -v p="${3:-roudi}" '$1==p {print $4}')
  kill "-$1" "$victim"
  for _ in $(seq 600); do
    [ "$(grep -c "; started" "$RUN/heal.log" 2>/dev/null || true)" -gt "$before" ] && break
    sleep 0.1
  done
  [ "$(grep -c "; started" "$RUN/heal.log" 2>/dev/null || true)" -gt "$before" ] \
    || fail "no heal after SIG$1 to RouDi: $(cat "$RUN/heal.log" 2>/dev/null) $($SUP status)"
  grep -q "$2" "$RUN/heal.log" || fail "heal.log does not say '$2': $(cat "$RUN/heal.log")"
  wait_flowing "$n" "$pid" || fail "frames do not flow after healing SIG$1: $($SUP status)"
  local new
  new=$($SUP status | awk '$1=="roudi" {print $4}')
  [ "$new" != "$roudi" ] || fail "RouDi pid unchanged after the heal"
  kill -0 "$roudi" 2>/dev/null && fail "the old RouDi (pid $roudi) still runs"
  pass "SIG$1 to ${3:-roudi} (pid $victim): healed ($(grep "; started" "$RUN/heal.log" | tail -1 | sed 's/.*; //')), new RouDi $new, frames flow"
}
heal_round KILL "RouDi exited"
heal_round STOP "RouDi stuck"
# The probe itself hangs: its status file goes stale and the watcher heals all the same.
heal_round STOP "stopped reporting" health

# A second pipeline (another run dir) refuses, naming the first; the first's files are untouched.
before=$(stat -c '%i %Y' "$RUN/supervisor.sock" "$RUN/supervisord.conf" "$RUN/logs")
if out=$("$SRC/deploy/dfsup" --run-dir "$TMP/run2" up "$TMP/pipeline.pbtxt" 2>&1); then
  fail "a second dfsup up started: $out"
fi
[[ "$out" == *"$RUN"* ]] || fail "the refusal does not name the running pipeline's run dir: $out"
[ ! -e "$TMP/run2/supervisord.conf" ] || fail "the refused up wrote a supervisord.conf"
if out2=$($SUP up "$TMP/pipeline.pbtxt" 2>&1); then fail "a second up on the same run dir started"; fi
[ "$before" = "$(stat -c '%i %Y' "$RUN/supervisor.sock" "$RUN/supervisord.conf" "$RUN/logs")" ] \
  || fail "a refused up touched the first run's files"
$SUP status >/dev/null || fail "the first pipeline does not answer after the refusals"
pass "second up refused: ${out#dfsup: error: }"

pids=$($SUP status | awk '$3 == "pid" && $4 ~ /^[0-9]+$/ && $4 != 0 {print $4}')
sup_pid=$(cat "$RUN/supervisord.pid")
sup_down
for p in $pids $sup_pid; do
  if kill -0 "$p" 2>/dev/null && [ "$(awk '{print $3}' "/proc/$p/stat")" != Z ]; then
    fail "pid $p still runs after down"
  fi
done
roudi_running && fail "RouDi still holds /tmp/roudi.lock after down"
pass "down: no program, supervisord or RouDi left (pids $(echo $pids) $sup_pid)"
