#!/usr/bin/env bash
# Exposure: a service with the default DDS settings (no CYCLONEDDS_URI) uses loopback only: it
# binds nothing to the LAN address, joins no multicast port, and a participant on another host
# (a network namespace behind a veth pair) that names this host as its peer does not discover
# its topic; the same service with `interfaces` and `peers` set is discovered (the control that
# shows the other host could see it). Cyclone 0.10 binds its two unicast receive sockets to
# 0.0.0.0 whatever the configuration (ddsi_udp.c): checked to be the only wildcard sockets.
source "$(dirname "$0")/lib.sh"
"$BIN/df_make_sequence" --preset default --out "$TMP/seq" --frames 5 >/dev/null 2>&1
capture() {  # ns, extra dds fields
  "$BIN/df_capture" --config "$SRC/deploy/config/capture_realtime.pbtxt" "$TMP/seq" \
    --set "dds { ns: \"$1\" transport: \"udp\" $2 }" >"$TMP/$1.log" 2>&1 &
  pids+=($!)
}
# Capture's real-time sleeps may outlast a SIGTERM: the captures are SIGKILLed at exit.
stop_captures() { for p in "${pids[@]:-}"; do [ -n "$p" ] && kill -KILL "$p" 2>/dev/null || true; done; }
trap 'stop_captures; cleanup' EXIT
capture "${NS}_lo" ""
lo_pid=$!
lan=$(ip -4 -o addr show scope global | awk '{print $4}' | cut -d/ -f1 | head -1)
for _ in $(seq 100); do [ "$(ss -lunpH | grep -c "pid=$lo_pid,")" -ge 3 ] && break; sleep 0.1; done
socks=$(ss -lunpH | grep "pid=$lo_pid," | awk '{print $4}')
[ -n "$socks" ] || fail "df_capture (pid $lo_pid) has no UDP sockets: $(tail -5 "$TMP/${NS}_lo.log")"
grep -q "network loopback only" "$TMP/${NS}_lo.log" || fail "no 'loopback only' line in the log"
if [ -n "$lan" ] && grep -q "^$lan:" <<<"$socks"; then fail "a socket is bound to the LAN address $lan: $socks"; fi
grep -qE ':740[01]$' <<<"$socks" && fail "a multicast discovery port (7400/7401) is bound: $socks"
grep -q '^127.0.0.1:' <<<"$socks" || fail "the transmit socket is not bound to 127.0.0.1: $socks"
wild=$(grep -c '^0.0.0.0:' <<<"$socks" || true)
[ "$wild" -le 2 ] || fail "more than Cyclone's two unicast receive sockets on 0.0.0.0: $socks"
pass "default participant: sockets $(echo $socks | tr '\n' ' ')(no LAN address, no multicast port)"

if [ "$(id -u)" -ne 0 ] || ! command -v ip >/dev/null; then
  echo "SKIP: the second-host part needs root for a network namespace"; exit 0
fi
net="dfx$$"; sub="10.$((200 + RANDOM % 50)).$((RANDOM % 250)).0"
host_ip="${sub%.0}.1"; remote_ip="${sub%.0}.2"
ip netns add "$net"
trap 'stop_captures; ip netns del "$net" 2>/dev/null || true; ip link del "${net}a" 2>/dev/null || true; cleanup' EXIT
ip link add "${net}a" type veth peer name "${net}b"
ip link set "${net}b" netns "$net"
ip addr add "$host_ip/24" dev "${net}a" && ip link set "${net}a" up
ip -n "$net" addr add "$remote_ip/24" dev "${net}b" && ip -n "$net" link set "${net}b" up
ip -n "$net" link set lo up  # Cyclone wakes its receive threads at exit through a local send
capture "${NS}_veth" "interfaces: \"${net}a\" peers: \"$remote_ip\""
sleep 1
timeout -s INT -k 5 30 ip netns exec "$net" "$BIN/df_tap" list --wait 4 --transport udp \
  --interfaces "${net}b" --peer "$host_ip" >"$TMP/remote.txt" 2>"$TMP/remote.err" \
  || fail "df_tap list on the other host: $(tail -3 "$TMP/remote.err")"
grep -q "^${NS}_veth/frames" "$TMP/remote.txt" \
  || fail "control: the service that opted in to ${net}a was not discovered: $(cat "$TMP/remote.txt")"
grep -q "^${NS}_lo/frames" "$TMP/remote.txt" \
  && fail "the loopback-only service was discovered from the other host: $(cat "$TMP/remote.txt")"
pass "from another host: the opted-in service is seen, the default (loopback) one is not"
exit 0
