#!/usr/bin/env bash
# kill -9 of any process of the main job, at any moment: the main job's pipeline
# (deploy/pipelines/default.pbtxt: capture in lockstep on SLAM and fusion, SLAM, geoseg, the
# detector, fusion; RouDi, df_health and the watcher) runs under dfsup on a short generated
# sequence, with the simulated detector to keep it fast. During the run each of capture, slam,
# geoseg, detector, fusion, health and RouDi is SIGKILLed once, in a seeded-random order, each
# after a seeded-random number of new poses (DF_KILL_SEED picks another order; DF_KILL_REPORT
# names a file that gets one line per kill, for tests/bench/run_kill_bench.sh). Then:
# - the run finishes: SLAM exits 0 and writes trajectory.txt, map.ply and summary.json;
# - no pose written before a kill is missing from the final trajectory, no stamp twice;
# - the frames without a pose are only those of SLAM's own outage: one run of consecutive frames
#   right after the last pose SLAM wrote before it was killed (capture waits for SLAM until its
#   lease runs out, then publishes without it until the restarted SLAM's reader appears), at
#   most MAX_GAP of them (the last pose read from trajectory.txt once the killed SLAM is gone);
#   a killed capture (and a healed RouDi, which restarts every service)
#   goes on after the last frame it recorded as done (its resume file), never from frame 0;
# - no lockstep wait ran into capture's 30 s timeout;
# - the ATE against the ground truth is within 3x + 0.5 cm of an unkilled run (df_slam offline
#   on the same frames, same SLAM library and defaults, the same simulated detector).
source "$(dirname "$0")/lib.sh"
if roudi_running; then
  echo "SKIP: a RouDi is already running on this machine; this test needs to start its own under dfsup"
  exit 77
fi
N=300
MAX_GAP=30
SEED="${DF_KILL_SEED:-7}"
RANDOM=$SEED
"$BIN/df_make_sequence" --preset static_xyz --out "$TMP/seq" --frames $N --no-models --threads 2 \
  >/dev/null 2>&1 || fail "df_make_sequence failed"
# The main job's pipeline as it is, with the simulated detector (boxes from the ground truth).
sed 's|  config: "deploy/config/detector_default.pbtxt"|&\n  args: ["--set", "model: \\"simulated\\"", "--set", "sim_sequence: \\"${DF_DATA}\\""]|' \
  "$SRC/deploy/pipelines/default.pbtxt" >"$TMP/pipeline.pbtxt"
grep -q 'sim_sequence' "$TMP/pipeline.pbtxt" || fail "could not switch the detector to simulated"
RUN="$TMP/run"
OUT="$TMP/out/slam"
SUP="$SRC/deploy/dfsup --run-dir $RUN"
$SUP up "$TMP/pipeline.pbtxt" --var "DF_DATA=$TMP/seq" --var "DF_NS=$NS" --var "DF_OUT=$TMP/out" \
  --var "DF_BUILD=$(dirname "$BIN")" >/dev/null
trap '$SUP down >/dev/null 2>&1 || true; cleanup' EXIT

poses() { local n; n=$(grep -vc '^#' "$OUT/trajectory.txt" 2>/dev/null) || true; echo "${n:-0}"; }
pid_of() { $SUP status | awk -v p="$1" '$1==p && $2=="RUNNING" {print $4}'; }
heals() { local n; n=$(grep -c "; started" "$RUN/heal.log" 2>/dev/null) || true; echo "${n:-0}"; }
# Waits (60 s at most) until the trajectory has at least $1 poses or SLAM exited.
wait_poses() {
  for _ in $(seq 1200); do
    [ "$(poses)" -ge "$1" ] && return 0
    $SUP status | grep -Eq '^slam +(EXITED|FATAL)' && return 1
    sleep 0.05
  done
  return 1
}
wait_poses 5 || fail "no poses after the start: $($SUP status)"
# When each pose appeared (wall time), for the stall after each kill.
/usr/bin/python3 - "$OUT/trajectory.txt" "$TMP/poses.txt" <<'PY' &
import os, sys, time
traj, out, n = sys.argv[1], sys.argv[2], -1
with open(out, "w", buffering=1) as f:
    while os.getppid() != 1:
        try:
            m = sum(1 for l in open(traj) if l.strip() and not l.startswith("#"))
        except OSError:
            m = n
        if m != n:
            f.write(f"{time.time():.3f} {m}\n"); n = m
        time.sleep(0.01)
PY
pids+=($!)
# Seconds from $2 (the kill, epoch s) until the restarted $1 answered (df_health's receive time
# of its new writer's first stage_status; capture: SLAM's and fusion's first answers of the new
# run epoch; RouDi: the first answers of the new SLAM and fusion; health: its start, when it
# writes its first status file).
back_of() {
  /usr/bin/python3 - "$RUN/health.json" "$1" "$2" "$TMP/health_before.json" <<'PY'
import json, sys, time
path, victim, t0, before_path = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
before = json.load(open(before_path))
def answered(j):
    st = j["stages"]
    def first(stage, key):
        a, b = st.get(stage), before["stages"].get(stage, {})
        if not a or (b and a[key] == b[key]):
            return None
        return j["wall_time_s"] - a[key + "_age_s"]
    if victim == "health":  # its first status file came with its start
        return j["wall_time_s"] - j["uptime_s"] if j["pid"] != before["pid"] else None
    if victim == "capture":
        w = [first(s, "epoch") for s in ("slam", "fusion")]
    elif victim == "roudi":
        w = [first(s, "writer") for s in ("slam", "fusion")]
    else:
        w = [first(victim, "writer")]
    return None if None in w else max(w)
deadline = time.time() + 30
while time.time() < deadline:
    try:
        j = json.load(open(path))
        w = answered(j)
        if w is not None:
            print(f"{w - t0:.2f}"); sys.exit(0)
    except (OSError, ValueError, KeyError):
        pass
    time.sleep(0.05)
print("nan")
PY
}

targets=(capture slam geoseg detector fusion health roudi)
for ((i = ${#targets[@]} - 1; i > 0; i--)); do  # seeded Fisher-Yates shuffle
  j=$((RANDOM % (i + 1))); t=${targets[i]}; targets[i]=${targets[j]}; targets[j]=$t
done
echo "kill order (seed $SEED): ${targets[*]}"
k=0
for victim in "${targets[@]}"; do
  k=$((k + 1))
  at=$(($(poses) + 2 + RANDOM % 4))
  [ "$at" -lt $((N - 6)) ] || fail "the run is nearly over before kill $k (${victim}); $(poses) poses"
  wait_poses "$at" || fail "trajectory stuck at $(poses) poses before killing $victim: $($SUP status)"
  sleep "0.$((RANDOM % 5))"
  # A heal (RouDi deadlocked by an earlier kill) stops and restarts every service: wait for it.
  for _ in $(seq 300); do pid=$(pid_of "$victim"); [ -n "$pid" ] && break; sleep 0.1; done
  [ -n "$pid" ] || fail "$victim is not running before its kill: $($SUP status)"
  h=$(heals)
  cp "$OUT/trajectory.txt" "$TMP/before_$victim.txt"
  cp "$RUN/health.json" "$TMP/health_before.json"
  t0=$(date +%s.%N)
  kill -KILL "$pid"
  if [ "$victim" = slam ]; then
    # Every pose the killed SLAM wrote (it appends each before it answers the frame): the
    # trajectory once the process is gone, before its restart appends to it.
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.02; done
    cp "$OUT/trajectory.txt" "$TMP/at_kill_slam.txt"
  fi
  for _ in $(seq 400); do  # restarted (or, for RouDi, healed)
    if [ "$victim" = roudi ]; then
      [ "$(heals)" -gt "$h" ] && break
    else
      new=$(pid_of "$victim"); [ -n "$new" ] && [ "$new" != "$pid" ] && break
    fi
    sleep 0.05
  done
  before=$(poses)
  if ! wait_poses $((before + 1)); then
    # Killed after the last frame went out: a restarted capture replays frames all tracked.
    $SUP status | grep -Eq '^slam +EXITED' && [ "$before" -ge $((N - MAX_GAP)) ] \
      || fail "no pose after killing $victim (pid $pid): $($SUP status)"
    pass "kill $k: $victim (pid $pid) at $before poses, after the last frame; the run finished"
    continue
  fi
  back=$(back_of "$victim" "$t0")
  pass "kill $k: $victim (pid $pid) at $before poses; answering again $back s after the kill"
  echo "$victim $t0 $back" >>"$TMP/kills.txt"
done

$SUP wait slam --timeout 240 >/dev/null || fail "SLAM did not finish cleanly: $($SUP status); $(tail -5 "$RUN/logs/slam.log")"
$SUP wait fusion --timeout 60 >/dev/null || fail "fusion did not finish cleanly: $(tail -5 "$RUN/logs/fusion.log")"
for f in trajectory.txt map.ply summary.json; do
  [ -s "$OUT/$f" ] || fail "SLAM wrote no $f after the kills"
done
if grep -q "no answer from stage" "$RUN/logs/capture.log"; then
  fail "a lockstep wait ran into its timeout: $(grep 'no answer' "$RUN/logs/capture.log" | head -3)"
fi
grep -q "heal .* because RouDi exited" "$RUN/heal.log" || fail "no heal logged for RouDi: $(cat "$RUN/heal.log")"
# Every restarted capture went on after its last frame done (or found the run played out).
starts=$(grep -c "lockstep: waiting up to\|nothing left to publish" "$RUN/logs/capture.log" || true)
fresh=$(grep -c "resume file .*: none yet, playing from frame 0" "$RUN/logs/capture.log" || true)
[ "$fresh" -eq 1 ] || fail "$fresh captures played from frame 0: $(grep 'resume file' "$RUN/logs/capture.log")"
resumed=$(grep -c "resume file .*: \(going on after\|the previous run played\)" "$RUN/logs/capture.log" || true)
[ "$resumed" -eq $((starts - 1)) ] \
  || fail "$((starts - 1)) capture restarts, $resumed resumed: $(grep 'resume file' "$RUN/logs/capture.log")"
replayed=$(grep -o "([0-9]* frame(s) tracked before it answered skipped)" "$RUN/logs/slam.log" \
  | tr -dc '0-9\n' | sort -n | tail -1)
[ "${replayed:-0}" -le 2 ] || fail "SLAM answered $replayed frames tracked already after a restart (a replay)"

/usr/bin/python3 - "$TMP" "$OUT/trajectory.txt" "$TMP/seq/groundtruth.txt" $MAX_GAP "${targets[@]}" <<'PY' \
  || fail "trajectory check"
import sys
tmp, traj, gt, max_gap, victims = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5:]
def stamps(path):
    return [round(float(l.split()[0]), 4) for l in open(path) if l.strip() and not l.startswith("#")]
final = stamps(traj)
dup = sorted({s for s in final if final.count(s) > 1})
assert not dup, f"stamps twice in the trajectory: {dup[:5]}"
have = set(final)
for v in victims:
    lost = [s for s in stamps(f"{tmp}/before_{v}.txt") if s not in have]
    assert not lost, f"{len(lost)} pose(s) written before the {v} kill are missing: {lost[:5]}"
frames = stamps(gt)
missing = [i for i, s in enumerate(frames) if s not in have]
at_kill = stamps(f"{tmp}/at_kill_slam.txt")
last = frames.index(at_kill[-1]) if at_kill else -1
gap = list(range(last + 1, last + 1 + len(missing)))
assert missing == gap, (f"frames {missing[:10]} have no pose; only a run right after frame {last} "
                        "(the last pose the killed SLAM wrote) may")
assert len(missing) <= max_gap, f"{len(missing)} frames of SLAM's outage have no pose (> {max_gap})"
import os
# Per kill: the longest time without a new pose from the kill until the next kill (15 s at
# most): the pipeline's stall, lockstep waits included.
# A new pose is a new highest count (SLAM rewrites the whole file at the end of the run).
appeared, most = [], 0
for l in open(f"{tmp}/poses.txt"):
    t, n = float(l.split()[0]), int(l.split()[1])
    if n > most:
        appeared.append(t); most = n
report = os.environ.get("DF_KILL_REPORT")
kills = [l.split() for l in open(f"{tmp}/kills.txt") if l.strip()]
for i, (victim, t0, back) in enumerate(kills):
    t0 = float(t0)
    end = min(t0 + 15, float(kills[i + 1][1]) if i + 1 < len(kills) else t0 + 15)
    later = [t for t in appeared if t0 < t <= end]
    edges = [t0] + later
    stall = max((b - a for a, b in zip(edges, edges[1:])), default=float("nan"))
    print(f"kill {victim}: answering again {back} s after it, longest time without a pose {stall:.2f} s")
    if report:
        with open(report, "a") as f:
            f.write(f"kill {victim} {back} {stall:.2f}\n")
if report:
    with open(report, "a") as f:
        f.write(f"lost {len(missing)} {len(frames)}\n")
print(f"ok: {len(final)} of {len(frames)} frames have a pose; none written before a kill lost; "
      f"no stamp twice; {len(missing)} frame(s) of SLAM's outage without one (after frame {last})")
PY

"$BIN/df_slam" offline "$TMP/seq" -o "$TMP/offline" --detector simulated >"$TMP/offline.log" 2>&1 || fail "df_slam offline failed"
"$BIN/df_eval" ate "$TMP/seq/groundtruth.txt" "$OUT/trajectory.txt" --json "$TMP/ate.json" >/dev/null \
  || fail "df_eval ate failed"
"$BIN/df_eval" ate "$TMP/seq/groundtruth.txt" "$TMP/offline/trajectory.txt" --json "$TMP/ate0.json" \
  >/dev/null || fail "df_eval ate of the unkilled run failed"
cm() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['ate']['translation_m']['rmse']*100)" "$1"; }
ate=$(cm "$TMP/ate.json"); ate0=$(cm "$TMP/ate0.json")
/usr/bin/python3 -c "import sys; a, b = map(float, sys.argv[1:]); sys.exit(0 if a <= 3 * b + 0.5 else 1)" \
  "$ate" "$ate0" || fail "ATE $ate cm after the kills; unkilled run $ate0 cm"
pass "run finished after 7 kills; ATE $ate cm (unkilled run: $ate0 cm); heals: $(heals)"
