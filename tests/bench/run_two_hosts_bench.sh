#!/usr/bin/env bash
# Detection on a second host, measured (issue 14; figures in docs/deploy.md): two hosts made of
# network namespaces (tests/two_hosts/netns.sh), deploy/pipelines/two_hosts.pbtxt on each, capture
# at 30 Hz REALTIME on host a, YOLOv5s on host b. For the clean link, a delay of 20 and 50 ms (tc
# netem, where the kernel has it), loss of 1 % and 5 % (nftables), and a 10 Mbit/s rate limit (tc
# tbf), it prints over a window of DF_BENCH_S seconds
# (default 10), all measured on host a:
# - color_small: bandwidth of the JPEG colour image that crosses to b;
# - detections: round trip from capture to the detections received back, over the frames the
#   detector detected (df_tap delay --ok-only), p50 / p99;
# - of the frames the detector detected, the share whose detections reached fusion in time (the
#   frame's first object_segments sample used them), and at all (also when fusion republished
#   the frame with late detections, republish_late_ms);
# - camera_pose rate.
# Then the link is cut for 5 s, and host b's pipeline is stopped for 5 s and started again: the
# pose rate meanwhile and how long until detections are used again. Needs root, iproute2 and the YOLOv5s model.
#   sudo bash tests/bench/run_two_hosts_bench.sh [SEQUENCE]   (default: build/data/default)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
BIN="${DF_BUILD:-$ROOT/build}/bin"
DATA="${1:-${DF_BUILD:-$ROOT/build}/data/default}"
WINDOW="${DF_BENCH_S:-10}"
HOSTS="$ROOT/tests/two_hosts/netns.sh"
export DF_HOSTS_PREFIX="${DF_HOSTS_PREFIX:-dfb}"
TMP="$(mktemp -d /tmp/df-two-hosts-bench-XXXXXX)"
NS="bench$$"
[ -d "$DATA" ] || { echo "no sequence at $DATA (build first)" >&2; exit 1; }
"$HOSTS" up >/dev/null
eval "$("$HOSTS" env)"
SUP_A="$HOSTS exec a $ROOT/deploy/dfsup --run-dir $TMP/run-a"
SUP_B="$HOSTS exec b $ROOT/deploy/dfsup --run-dir $TMP/run-b"
teardown() {
  $SUP_B down >/dev/null 2>&1 || true; $SUP_A down >/dev/null 2>&1 || true
  "$HOSTS" down; rm -rf "$TMP"
}
trap teardown EXIT
"$ROOT/deploy/security/make_certs.sh" "$TMP/sec" a b >/dev/null
SEC="$TMP/sec"  # DDS Security on, as the pipeline has it; "" for the run without
vars() {
  local ifc=$IF_A; [ "$1" = b ] && ifc=$IF_B
  echo "--var DF_DATA=$DATA --var DF_NS=$NS --var DF_OUT=$TMP/out-$1 --var DF_BUILD=$(dirname "$BIN")" \
       "--var DF_IFACE=$ifc --var DF_ADDR_A=$ADDR_A --var DF_ADDR_B=$ADDR_B --var DF_SECURITY_DIR=$SEC"
}
tap() {  # the bench's taps on host a, with the pipeline's security
  if [ -n "$SEC" ]; then
    $HOSTS exec a "$BIN/df_tap" --interfaces "$IF_A" --peer "$ADDR_A" --peer "$ADDR_B" --security-dir "$SEC" --identity a "$@"
  else
    $HOSTS exec a "$BIN/df_tap" --interfaces "$IF_A" --peer "$ADDR_A" --peer "$ADDR_B" "$@"
  fi
}
TAP=tap
start() {
  $SUP_A up "$ROOT/deploy/pipelines/two_hosts.pbtxt" --host a $(vars a) >/dev/null
  $SUP_B up "$ROOT/deploy/pipelines/two_hosts.pbtxt" --host b $(vars b) >/dev/null
  # Until the detector's first detections are used (model load, discovery).
  for _ in $(seq 600); do
    $TAP echo "$NS/object_segments" --items 0 -n 30 --wait 2 2>/dev/null | grep -q "detections_used: true" && break
    sleep 0.1
  done
}
start

pids_a() { $SUP_A status | awk '$2=="RUNNING" {print $1 "=" $4}' | sort | tr '\n' ' '; }
before_pids=$(pids_a)

share() {  # share DETECTIONS_ECHO SEGMENTS_ECHO: detected frames, of them used in time
  /usr/bin/python3 - "$1" "$2" <<'PY'
import re, sys
def msgs(path):
    for m in open(path, errors="replace").read().split("header:")[1:]:
        seq = re.search(r"\bseq:\s*(\d+)", m); st = re.search(r"\bstatus:\s*(\w+)", m)
        yield m, int(seq.group(1)) if seq else -1, st.group(1) if st else ""
detected = {seq for _, seq, st in msgs(sys.argv[1]) if st in ("OK", "FRAME_OK")}
first, any_used = {}, set()
for m, seq, _ in msgs(sys.argv[2]):
    u = re.search(r"detections_used:\s*(\w+)", m)
    used = bool(u) and u.group(1) == "true"
    if seq not in first:
        first[seq] = used
    if used:
        any_used.add(seq)
seen = [s for s in detected if s in first]
print(len(seen), sum(first[s] for s in seen), sum(s in any_used for s in seen))
PY
}
TICKS=$(getconf CLK_TCK)
# CPU ticks used so far by the pipeline's services on both hosts (their arguments name the
# namespace; the bench's taps do not count).
pipeline_ticks() {
  local t=0 p f
  for p in $(pgrep -f "ns: \"$NS\"" || true); do
    read -r -a f <<<"$(sed 's/^.*) //' "/proc/$p/stat" 2>/dev/null)" || continue
    [ "${#f[@]}" -gt 12 ] && t=$((t + f[11] + f[12]))
  done
  echo "$t"
}
measure() {  # measure LABEL
  local d="$TMP/m"; rm -rf "$d"; mkdir -p "$d"
  $TAP hz "$NS/camera_pose" --duration "$WINDOW" >"$d/hz" 2>&1 &
  local p1=$! cpu0 ticks0 wall0; cpu0=$(head -1 /proc/stat); ticks0=$(pipeline_ticks); wall0=$(date +%s.%N)
  $TAP bw "$NS/color_small" --duration "$WINDOW" >"$d/bw" 2>&1 &
  local p2=$!
  $TAP delay "$NS/detections" --ok-only --window 100000 --duration "$WINDOW" >"$d/delay" 2>&1 &
  local p3=$!
  $TAP echo "$NS/detections" --items 0 --depth 256 --duration "$WINDOW" >"$d/det" 2>&1 &
  local p4=$!
  $TAP echo "$NS/object_segments" --items 0 --depth 256 --duration "$WINDOW" >"$d/seg" 2>&1 &
  local p5=$!
  wait $p1 $p2 $p3 $p4 $p5 || true
  local services; services=$(awk -v a="$ticks0" -v b="$(pipeline_ticks)" -v t="$TICKS" \
    -v w0="$wall0" -v w1="$(date +%s.%N)" 'BEGIN { printf "%.0f", 100 * (b - a) / t / (w1 - w0) }')
  local hz bw dl s busy
  busy=$(/usr/bin/python3 -c "import sys; a=list(map(int,sys.argv[1].split()[1:])); b=list(map(int,sys.argv[2].split()[1:])); d=[y-x for x,y in zip(a,b)]; idle=d[3]+d[4]; print(f'{100*(sum(d)-idle)/max(1,sum(d)):.0f}')" "$cpu0" "$(head -1 /proc/stat)")
  hz=$(awk '/average rate:/ {r=$3} END {printf "%.1f", r+0}' "$d/hz")
  bw=$(awk '/average:/ {r=$2 " " $3} END {print r}' "$d/bw")
  dl=$(awk '/delay \(receive/ {r=sprintf("%.0f / %.0f ms", $9, $12)} END {print (r == "" ? "none" : r)}' "$d/delay")
  read -r seen used late < <(share "$d/det" "$d/seg")
  s=$( [ "$seen" -gt 0 ] && /usr/bin/python3 -c "import sys; n, a, b = map(int, sys.argv[1:]); print(f'{n} detected: {100*a/n:.0f} % in time, {100*b/n:.0f} % used at all')" "$seen" "$used" "$late" || echo "no frame detected")
  printf "%-12s color_small %-10s detections p50/p99 %-13s camera_pose %4s Hz  cpu %s %% (services %s %% of a core)  %s\n" \
    "$1" "$bw" "$dl" "$hz" "$busy" "$services" "$s"
}
echo "two hosts ($NS_A, $NS_B; $IF_A $ADDR_A <-> $IF_B $ADDR_B), $(basename "$DATA") at 30 Hz, windows of $WINDOW s"
measure "clean"
for cond in "delay 20ms" "delay 50ms" "loss 1" "loss 5" "rate 10mbit"; do
  # shellcheck disable=SC2086
  if ! "$HOSTS" shape $cond 2>"$TMP/shape.err"; then
    printf "%-16s not measured: %s\n" "$cond" "$(cat "$TMP/shape.err")"
    continue
  fi
  sleep 2
  measure "$cond"
  "$HOSTS" shape clear
done
sleep 2
# fault NAME BREAK MEND: the pose rate while BREAK holds for 5 s, and how soon after MEND a
# frame used detections again.
fault() {
  $TAP hz "$NS/camera_pose" --duration 6 >"$TMP/hz_fault" 2>&1 &
  local hzp=$!
  $TAP echo "$NS/object_segments" --items 0 --depth 256 --duration 20 >"$TMP/seg_fault" 2>&1 &
  local segp=$!
  sleep 1
  eval "$2"; sleep 5
  local back; back=$(date +%s%N)
  eval "$3"
  wait $hzp || true; wait $segp || true
  local rec
  rec=$(/usr/bin/python3 - "$TMP/seg_fault" "$back" <<'PY'
import re, sys
best = None
for m in open(sys.argv[1], errors="replace").read().split("header:")[1:]:
    c = re.search(r"capture_ns:\s*(\d+)", m); u = re.search(r"detections_used:\s*(\w+)", m)
    if c and u and u.group(1) == "true" and int(c.group(1)) > int(sys.argv[2]):
        t = (int(c.group(1)) - int(sys.argv[2])) / 1e9
        best = t if best is None else min(best, t)
print("not within 14 s" if best is None else f"{best:.2f} s")
PY
)
  printf "%-16s camera_pose %s Hz meanwhile; detections used again on a frame captured %s after it ended\n" \
    "$1" "$(awk '/average rate:/ {r=$3} END {printf "%.1f", r+0}' "$TMP/hz_fault")" "$rec"
}
fault "link cut 5 s" '"$HOSTS" cut' '"$HOSTS" restore'
# Host b stopped and started again with its supervisor (a restarted detector host; the detector
# loads YOLOv5s first).
fault "host b down 5 s" '$SUP_B down >/dev/null' \
  '$SUP_B up "$ROOT/deploy/pipelines/two_hosts.pbtxt" --host b $(vars b) >/dev/null'
after_pids=$(pids_a)
if [ "$before_pids" = "$after_pids" ]; then
  echo "host a: no process restarted ($after_pids)"
else
  echo "host a: processes restarted: before $before_pids, after $after_pids"
fi
# What security costs: the clean link again, both hosts restarted without it.
$SUP_B down >/dev/null; $SUP_A down >/dev/null
SEC=""
start
measure "clean, no DDS Security"
