#!/usr/bin/env bash
# Healing under load: capture (30 Hz, looping) -> geoseg, simulated detector, fusion over shared
# memory under dfsup with df_health and the watcher. Measures, N times each (HEAL_BENCH_N,
# default 20): SIGKILL of RouDi -> seconds until frames flow again (the first answer of the
# restarted fusion, after the watcher's heal; target 5 s); SIGKILL of each service -> seconds
# until the restarted process answers (capture: until fusion answers a frame of the new capture
# run; target 2 s). Times are df_health's receive times (services answer every frame). Prints a table and
# writes $OUT/heal_bench.json. Needs the machine to itself (it starts its own RouDi).
#   bash tests/bench/run_heal_bench.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
out="${2:-$root/out/heal_bench}"
n="${HEAL_BENCH_N:-20}"
mkdir -p "$out"
if [ -e /tmp/roudi.lock ] && ! flock -n /tmp/roudi.lock true; then
  echo "a RouDi already runs on this machine: stop it first" >&2; exit 1
fi
seq_dir="$out/seq"
[ -f "$seq_dir/associations.txt" ] || "$build/bin/df_make_sequence" --preset default --out "$seq_dir" --frames 60 >/dev/null
cat > "$out/pipeline.pbtxt" <<PB
name: "heal-bench"
service { name: "geoseg" binary: "df_geoseg" args: ["--set", "dds { ns: \"\${DF_NS}\" }"] priority: 50 }
service {
  name: "detector" binary: "df_detector" priority: 50
  args: ["--set", "dds { ns: \"\${DF_NS}\" }", "--set", "model: \"simulated\"", "--set", "sim_sequence: \"\${DF_DATA}\""]
}
service {
  name: "fusion" binary: "df_fusion" config: "deploy/config/fusion_default.pbtxt"
  args: ["--set", "dds { ns: \"\${DF_NS}\" }"] priority: 50
}
service {
  name: "capture" binary: "df_capture" config: "deploy/config/capture_realtime.pbtxt"
  args: ["\${DF_DATA}", "--set", "dds { ns: \"\${DF_NS}\" }"]
}
PB
run="$out/run"
sup=("$root/deploy/dfsup" --run-dir "$run")
"${sup[@]}" up "$out/pipeline.pbtxt" --var "DF_DATA=$seq_dir" --var "DF_NS=hb$$" \
  --var "DF_OUT=$out" --var "DF_BUILD=$build"
trap '"${sup[@]}" down >/dev/null || true' EXIT
/usr/bin/python3 - "$run" "$n" "$out/heal_bench.json" "${sup[@]}" <<'PY'
import json, os, signal, statistics, subprocess, sys, time
run, n, out_json, sup = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4:]

def status():
    r = subprocess.run(sup + ["status"], capture_output=True, text=True)
    return {l.split()[0]: l.split() for l in r.stdout.splitlines() if l.strip()}

def pid_of(name):
    s = status().get(name)
    return int(s[3]) if s and s[1] == "RUNNING" and s[2] == "pid" else None

def health():
    try:
        return json.load(open(os.path.join(run, "health.json")))
    except (OSError, ValueError):
        return None

def answer(stage):
    """(health pid, the stage's answer dict with wall times added) or (pid, None)."""
    j = health()
    if not j:
        return None, None
    a = j["stages"].get(stage)
    if a:
        a = dict(a)
        for k in ("age_s", "writer_age_s", "epoch_age_s"):
            a[k.replace("age_s", "wall")] = j["wall_time_s"] - a[k]
    return j["pid"], a

def wait_for(pred, timeout=60):
    t = time.time()
    while time.time() < t + timeout:
        v = pred()
        if v is not None:
            return v
        time.sleep(0.02)
    return None

def wait_answer_after(stage, t, timeout=60):
    def fresh():
        _, a = answer(stage)
        return a["wall"] - t if a and a["wall"] > t else None
    return wait_for(fresh, timeout)

def settle():
    t = time.time()
    for stage in ("geoseg", "detector", "fusion"):
        if wait_answer_after(stage, t) is None:
            sys.exit(f"{stage} does not answer: {status()}")
    time.sleep(1.0)

settle()
results = {}
for target in ["roudi", "capture", "geoseg", "detector", "fusion"]:
    times = []
    for i in range(n):
        pid = None
        for _ in range(300):
            pid = pid_of(target)
            if pid:
                break
            time.sleep(0.05)
        if not pid:
            sys.exit(f"{target} not running: {status()}")
        hpid, fusion0 = answer("fusion")
        _, own0 = answer(target)
        t = time.time()
        os.kill(pid, signal.SIGKILL)
        # Frames flowing again = the first answer only a restarted process can give, as df_health
        # received it: RouDi: the first answer of a new fusion writer (every process is restarted;
        # until the heal the old ones go on over the orphaned segment); capture: the first fusion
        # answer of the new capture's run epoch; a service: the first answer of its new writer.
        def flowing():
            p, a = answer("fusion" if target in ("roudi", "capture") else target)
            if not a:
                return None
            if target == "roudi":
                ok = p != hpid or a["writer"] != fusion0["writer"]
                return a["writer_wall"] - t if ok and a["writer_wall"] > t else None
            if target == "capture" and fusion0["epoch"] == 0:  # a build without run epochs
                _, c = answer("capture")
                return c["writer_wall"] - t if c and c["writer"] != own0["writer"] else None
            if target == "capture":
                ok = a["epoch"] != fusion0["epoch"] and a["epoch_wall"] > t
                return a["epoch_wall"] - t if ok else None
            return a["writer_wall"] - t if a["writer"] != own0["writer"] else None
        dt = wait_for(flowing)
        times.append(dt)
        print(f"{target:<9} kill {i + 1:>2}: {'no answer within 60 s' if dt is None else f'{dt:.2f} s'}",
              flush=True)
        settle()
    ok = [x for x in times if x is not None]
    results[target] = {"tries": n, "flowing_again_s": times,
                       "median_s": statistics.median(ok) if ok else None,
                       "max_s": max(ok) if ok else None, "failed": n - len(ok)}
json.dump(results, open(out_json, "w"), indent=1)
print("\nSIGKILL of       tries  median s  max s  no recovery")
for k, r in results.items():
    med = "-" if r["median_s"] is None else f"{r['median_s']:.2f}"
    mx = "-" if r["max_s"] is None else f"{r['max_s']:.2f}"
    print(f"{k:<15} {r['tries']:>6} {med:>9} {mx:>6} {r['failed']:>12}")
PY
echo "heals logged: $(grep -c "; started" "$run/heal.log"), of which for a stuck RouDi:" \
  "$(grep -c ": RouDi stuck" "$run/heal.log" || true)"
