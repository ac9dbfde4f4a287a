#!/usr/bin/env bash
# Two hosts on one machine: network namespaces "<P>a" and "<P>b" joined by a veth pair, with
# addresses of a private test range that exist inside the namespaces only (the machine's own
# interfaces and routes are not touched). Needs root and iproute2 (ip, tc).
#
#   netns.sh up              make the namespaces, the link and the addresses (fails if they exist)
#   netns.sh down            remove them (and every process still in them); never fails
#   netns.sh cut | restore   take host a's end of the link down / up
#   netns.sh shape delay 20ms | loss 5 | rate 10mbit | clear
#                            degrade both ends of the link: delay with tc netem (not every kernel
#                            has it), loss (a percentage of the packets sent, dropped by nftables),
#                            rate with tc tbf; clear removes all three
#   netns.sh exec a|b CMD... run CMD on host a or b
#   netns.sh env             print the settings below as shell assignments
#
# Settings (environment): DF_HOSTS_PREFIX (default "df": namespaces dfa and dfb, veth dfva and
# dfvb), DF_HOSTS_SUBNET (default 10.213.7: host a is .1, host b is .2, /24).
# docs/deploy.md, "Two hosts on one machine".
set -euo pipefail
P="${DF_HOSTS_PREFIX:-df}"
NET="${DF_HOSTS_SUBNET:-10.213.7}"
NS_A="${P}a"; NS_B="${P}b"; IF_A="${P}va"; IF_B="${P}vb"
ADDR_A="$NET.1"; ADDR_B="$NET.2"

die() { echo "netns.sh: error: $*" >&2; exit 1; }
[ ${#IF_A} -le 15 ] || die "DF_HOSTS_PREFIX '$P' too long (interface names have at most 15 characters)"

case "${1:-}" in
  up)
    [ "$(id -u)" = 0 ] || die "needs root (ip netns)"
    command -v ip >/dev/null || die "ip (iproute2) not installed"
    for n in "$NS_A" "$NS_B"; do
      ! ip netns list | grep -qw "$n" || die "namespace $n exists: '$0 down' first"
    done
    ip netns add "$NS_A" || die "cannot create network namespace $NS_A"
    ip netns add "$NS_B" || { ip netns del "$NS_A"; die "cannot create network namespace $NS_B"; }
    if ! { ip link add "$IF_A" netns "$NS_A" type veth peer name "$IF_B" netns "$NS_B" &&
           ip -n "$NS_A" addr add "$ADDR_A/24" dev "$IF_A" &&
           ip -n "$NS_B" addr add "$ADDR_B/24" dev "$IF_B" &&
           ip -n "$NS_A" link set lo up && ip -n "$NS_B" link set lo up &&
           ip -n "$NS_A" link set "$IF_A" up && ip -n "$NS_B" link set "$IF_B" up; }; then
      ip netns del "$NS_A" 2>/dev/null || true; ip netns del "$NS_B" 2>/dev/null || true
      die "cannot set up the veth link between $NS_A and $NS_B"
    fi
    echo "netns.sh: host a = namespace $NS_A ($IF_A $ADDR_A), host b = namespace $NS_B ($IF_B $ADDR_B)"
    ;;
  down)
    for n in "$NS_A" "$NS_B"; do
      if ip netns list 2>/dev/null | grep -qw "$n"; then
        for pid in $(ip netns pids "$n" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null || true; done
        ip netns del "$n" 2>/dev/null || true
      fi
    done
    ;;
  cut) ip -n "$NS_A" link set "$IF_A" down ;;
  restore) ip -n "$NS_A" link set "$IF_A" up ;;
  shape)
    # Both ends of the link, so each direction is affected alike.
    shift; what="${1:-}"; arg="${2:-}"
    case "$what" in
      delay)
        [ -n "$arg" ] || die "shape delay needs a time, e.g. 20ms"
        for e in "$NS_A $IF_A" "$NS_B $IF_B"; do
          read -r n i <<<"$e"
          tc -n "$n" qdisc replace dev "$i" root netem delay "$arg" 2>/dev/null ||
            die "tc netem refused 'delay $arg' on $i: this kernel has no netem qdisc (sch_netem), so delay cannot be emulated here"
        done ;;
      loss)
        [[ "$arg" =~ ^[0-9]+$ ]] && [ "$arg" -le 100 ] || die "shape loss needs a whole percentage 0-100, got '$arg'"
        command -v nft >/dev/null || die "nft (nftables) not installed: deploy/setup.sh installs it"
        for e in "$NS_A $IF_A" "$NS_B $IF_B"; do
          read -r n i <<<"$e"
          ip netns exec "$n" nft delete table inet dfshape 2>/dev/null || true
          ip netns exec "$n" nft -f - <<NFT || die "nft refused the loss rule in $n"
table inet dfshape {
  chain out {
    type filter hook output priority 0;
    oifname "$i" numgen random mod 100 < $arg drop
  }
}
NFT
        done ;;
      rate)
        [ -n "$arg" ] || die "shape rate needs a rate, e.g. 10mbit"
        for e in "$NS_A $IF_A" "$NS_B $IF_B"; do
          read -r n i <<<"$e"
          tc -n "$n" qdisc replace dev "$i" root tbf rate "$arg" burst 64kbit latency 400ms ||
            die "tc refused 'rate $arg' on $i"
        done ;;
      clear)
        for e in "$NS_A $IF_A" "$NS_B $IF_B"; do
          read -r n i <<<"$e"
          tc -n "$n" qdisc del dev "$i" root 2>/dev/null || true
          ip netns exec "$n" nft delete table inet dfshape 2>/dev/null || true
        done ;;
      *) die "shape: delay TIME | loss PERCENT | rate RATE | clear, got '$what'" ;;
    esac
    ;;
  exec)
    shift; h="${1:-}"; shift || true
    case "$h" in a) n="$NS_A" ;; b) n="$NS_B" ;; *) die "exec: host must be a or b, got '$h'" ;; esac
    exec ip netns exec "$n" "$@"
    ;;
  env)
    echo "NS_A=$NS_A NS_B=$NS_B IF_A=$IF_A IF_B=$IF_B ADDR_A=$ADDR_A ADDR_B=$ADDR_B"
    ;;
  *) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
