#!/usr/bin/env bash
# scripts/netns.sh (issue 23): robots as network namespaces. Sourced by the team tests, the team
# benchmarks (quiver bench team embeds it) and scripts/team_traffic.sh, or run
# directly as a self-test (`netns.sh selftest`). One namespace per robot (NS_TAG-ROBOT, eth0 =
# 10.77.0.I/24) and one holding the bridge (NS_TAG-br: br0 + v-ROBOT); nothing in the caller's
# namespace. Everything made is removed by the EXIT trap, even on failure; stale namespaces of
# runs whose process is gone are swept first. No root / no `ip netns`: exit 77 (ctest
# SKIP_RETURN_CODE), or 1 with QUIVER_REQUIRE_NETNS=1.
NETNS_SKIP=77
QV_NS_PREFIX=${QV_NS_PREFIX:-qvt}          # tests: qvt; by hand: anything else
NETNS_NET=${NETNS_NET:-10.77.0}            # robot I (1-based, in netns_up order) is $NETNS_NET.I
NS_TAG="$QV_NS_PREFIX-$$"                  # this run's namespaces: qvt-<pid>-br, qvt-<pid>-A, ...
NS_MADE=() NS_PIDS=()
declare -A NETNS_ADDR=()

netns_skip() {  # REASON
  if [ "${QUIVER_REQUIRE_NETNS:-0}" = 1 ]; then
    echo "FAIL: QUIVER_REQUIRE_NETNS=1 and $1" >&2; exit 1
  fi
  echo "SKIP: $1: the team tests need root and iproute2 with network namespaces, veth and bridges" \
       "(set QUIVER_REQUIRE_NETNS=1 to make this a failure)" >&2
  exit "$NETNS_SKIP"
}
netns_cleanup() {  # processes we started, then our namespaces (their veths and bridge go with them)
  local p ns
  for p in "${NS_PIDS[@]}"; do kill -9 "$p" 2>/dev/null; done
  wait 2>/dev/null  # reaped here, so that bash does not report each as "Killed"
  for ns in "${NS_MADE[@]}"; do
    for p in $(ip netns pids "$ns" 2>/dev/null); do kill -9 "$p" 2>/dev/null; done
    ip netns del "$ns" 2>/dev/null
  done
  NS_PIDS=() NS_MADE=()
}
netns_sweep() {  # namespaces of our prefix whose creating shell is gone
  local ns pid p
  for ns in $(ip netns list 2>/dev/null | awk '{print $1}' | grep -E "^$QV_NS_PREFIX-[0-9]+-"); do
    pid=${ns#"$QV_NS_PREFIX"-}; pid=${pid%%-*}
    kill -0 "$pid" 2>/dev/null && continue
    for p in $(ip netns pids "$ns" 2>/dev/null); do kill -9 "$p" 2>/dev/null; done
    ip netns del "$ns" 2>/dev/null && echo "swept stale namespace $ns"
  done
}
netns_add() {  # NAME: lo up, IPv6 off (no DAD/MLD chatter in the traffic counts)
  ip netns add "$1" || return 1
  NS_MADE+=("$1")
  ip netns exec "$1" sysctl -qw net.ipv6.conf.all.disable_ipv6=1 net.ipv6.conf.default.disable_ipv6=1
  ip -n "$1" link set lo up
}
netns_require() {  # skip (or fail) unless we can make namespaces, veths and bridges; installs the trap
  [ "$(id -u)" = 0 ] || netns_skip "not running as root"
  command -v ip >/dev/null 2>&1 || netns_skip "no ip command (iproute2)"
  ip netns list >/dev/null 2>&1 || netns_skip "ip netns does not work here"
  trap netns_cleanup EXIT
  trap 'exit 130' INT TERM
  netns_sweep
  netns_add "$NS_TAG-probe" 2>/dev/null || netns_skip "cannot create a network namespace"
  ip -n "$NS_TAG-probe" link add p0 type veth peer name p1 2>/dev/null || netns_skip "no veth support"
  ip -n "$NS_TAG-probe" link add b0 type bridge 2>/dev/null || netns_skip "no bridge support"
  netns_cleanup
}
netns_up() {  # ROBOT...: the bridge namespace, then one namespace per robot joined to it
  local br="$NS_TAG-br" i=0 r ns
  netns_add "$br" && ip -n "$br" link add br0 type bridge && ip -n "$br" link set br0 up || return 1
  for r in "$@"; do
    i=$((i + 1)) ns="$NS_TAG-$r"
    netns_add "$ns" || return 1
    ip -n "$ns" link add eth0 type veth peer name "v-$r" netns "$br" || return 1
    ip -n "$br" link set "v-$r" master br0 && ip -n "$br" link set "v-$r" up || return 1
    ip -n "$ns" addr add "$NETNS_NET.$i/24" dev eth0 && ip -n "$ns" link set eth0 up || return 1
    NETNS_ADDR[$r]=$NETNS_NET.$i
  done
}
netns_team_file() {  # FILE ROBOT...: a team file (team domain 7) listing the robots netns_up made
  local file=$1 r sep=""
  shift
  {
    echo "{\"team\": \"$NS_TAG\", \"domain\": 7, \"lease_s\": 1, \"robots\": ["
    for r in "$@"; do echo "$sep{\"name\": \"$r\", \"address\": \"${NETNS_ADDR[$r]}\"}"; sep=","; done
    echo "]}"
  } >"$file"
}
netns_cut()  { ip -n "$NS_TAG-br" link set "v-$1" down; }   # ROBOT: unplug it at the switch
netns_heal() { ip -n "$NS_TAG-br" link set "v-$1" up; }
netns_slow() { tc -n "$NS_TAG-$1" qdisc replace dev eth0 root tbf rate "$2" burst 32kbit latency 400ms; }  # ROBOT RATE
netns_fast() { tc -n "$NS_TAG-$1" qdisc del dev eth0 root 2>/dev/null; }
netns_tx_bytes() { ip netns exec "$NS_TAG-$1" cat /sys/class/net/eth0/statistics/tx_bytes; }
netns_run() {  # ROBOT LOG CMD...: CMD in the robot's namespace, in the background; sets $started
  local ns="$NS_TAG-$1" log=$2; shift 2
  ip netns exec "$ns" "$@" >>"$log" 2>&1 &
  started=$!; NS_PIDS+=("$started")
}

if [ "${BASH_SOURCE[0]}" = "$0" ] && [ "${1:-}" = selftest ]; then
  set -u
  netns_require
  netns_up A B || { echo "FAIL: setup"; exit 1; }
  [ "$(ip -n "$NS_TAG-A" -br addr show eth0 | awk '{print $3}')" = "$NETNS_NET.1/24" ] || { echo "FAIL: address"; exit 1; }
  netns_cut A && ip -n "$NS_TAG-br" -br link show v-A | grep -q DOWN || { echo "FAIL: cut"; exit 1; }
  netns_heal A && netns_slow B 1mbit && netns_fast B || { echo "FAIL: heal/tbf"; exit 1; }
  echo "ok: $(ip netns list | grep -c "^$NS_TAG-") namespaces, tx_bytes(A)=$(netns_tx_bytes A)"
fi
