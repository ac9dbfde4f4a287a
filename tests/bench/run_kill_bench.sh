#!/usr/bin/env bash
# kill -9 under load: the main job's pipeline (tests/integration/kill_main_job_test.sh: capture
# in lockstep on SLAM and fusion, SLAM, geoseg, simulated detector, fusion, df_health, RouDi under
# dfsup, 200 generated frames) run ROUNDS times (KILL_BENCH_ROUNDS, default 20) with seeds
# 1..ROUNDS (or the seeds KILL_BENCH_SEEDS lists); each round SIGKILLs every one of the seven
# processes once, in that seed's order.
# KILL_BENCH_HOGS (default 1) busy loops run alongside (load). Prints per process the median and
# max of "back" (seconds from the SIGKILL until the restarted process answered again, as df_health
# received it; RouDi: the restarted SLAM and fusion) and "stall" (the longest time without a new
# SLAM pose after the kill: lockstep waits included), how many kills missed the target (2 s, 5 s
# for RouDi), and the frames without a pose per round.
#   bash tests/bench/run_kill_bench.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
out="${2:-$root/out/kill_bench}"
rounds="${KILL_BENCH_ROUNDS:-20}"
seeds="${KILL_BENCH_SEEDS:-$(seq "$rounds")}"  # or a list: KILL_BENCH_SEEDS="3 7 11"
rounds=$(echo $seeds | wc -w)
mkdir -p "$out"
report="$out/kills.txt"
: >"$report"
hogs=()
for _ in $(seq "${KILL_BENCH_HOGS:-1}"); do
  nice -n 0 bash -c 'while :; do :; done' & hogs+=($!)
done
trap 'for h in "${hogs[@]:-}"; do [ -n "$h" ] && kill "$h" 2>/dev/null; done' EXIT
failed=0
for r in $seeds; do
  echo "round seed $r" >>"$report"
  if ! DF_KILL_SEED=$r DF_KILL_REPORT="$report" DF_TEST_BIN="$build/bin" DF_TEST_SRC="$root" \
      bash "$root/tests/integration/kill_main_job_test.sh" >"$out/round_$r.log" 2>&1; then
    failed=$((failed + 1))
    echo "round $r FAILED: $(grep FAIL "$out/round_$r.log" | head -1)"
  fi
done
/usr/bin/python3 - "$report" "$rounds" "$failed" <<'PY'
import math, statistics, sys
lines = [l.split() for l in open(sys.argv[1]) if l.strip()]
rounds, failed = int(sys.argv[2]), int(sys.argv[3])
kills, lost = {}, []
for l in lines:
    if l[0] == "kill":
        kills.setdefault(l[1], []).append((float(l[2]), float(l[3])))
    elif l[0] == "lost":
        lost.append((int(l[1]), int(l[2])))
print(f"{rounds} rounds ({failed} failed). back: seconds from the SIGKILL until the restarted "
      "process answered; stall: longest time without a new SLAM pose after the kill")
print(f"{'process':<10} {'kills':>5} {'back median':>12} {'back max':>9} {'stall median':>13} "
      f"{'stall max':>10} {'over target':>12}")
for name in ("capture", "slam", "geoseg", "detector", "fusion", "health", "roudi"):
    v = kills.get(name, [])
    if not v:
        continue
    target = 5.0 if name == "roudi" else 2.0
    back = [b for b, _ in v if not math.isnan(b)]
    stall = [s for _, s in v if not math.isnan(s)]
    over = sum(1 for b, s in v if math.isnan(b) or b > target or s > target)
    med = lambda x: f"{statistics.median(x):.2f}" if x else "-"
    mx = lambda x: f"{max(x):.2f}" if x else "-"
    print(f"{name:<10} {len(v):>5} {med(back):>12} {mx(back):>9} {med(stall):>13} {mx(stall):>10} "
          f"{over:>8} of {len(v)}")
if lost:
    print(f"frames without a pose per round (all in SLAM's own outage): median "
          f"{statistics.median([m for m, _ in lost])}, max {max(m for m, _ in lost)} of {lost[0][1]}")
PY
exit $((failed > 0))
