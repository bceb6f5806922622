#!/usr/bin/env bash
# Faults between robots with real processes (docs/teams.md): three robots as network namespaces
# (scripts/netns.sh), each a gateway and an agent that stays (X-a2); short-lived writers make
# the changes. The team domain loses 20% of what the gateways send throughout
# (--team-loss-permille 200). Phases, each ending with every running replica equal and no
# equivocation, divergence or rejected sample:
#  1. both robots write at once;
#  2. robot A's link is slow (tbf, 256 kbit/s) while A writes;
#  3. robot B's gateway is killed (SIGKILL): both robots write, B's agents keep working alone;
#     the gateway restarts and catches up;
#  4. all of robot B's processes are killed at once (SIGKILL) while one of them counts and A
#     writes; restarted from their stores (--durability always), no acknowledged count is lost;
#  5. robot C joins the team late and catches up;
#  6. robot C leaves for good (SIGTERM): the others see its gateway go.
# Usage: gateway_faults_netns_test.sh QUIVER   (exit 77: skipped without root, see netns.sh)
set -uo pipefail
QUIVER=$1
. "$(dirname "$0")/gateway_lib.sh"
team_up A B C
ROBOTS=(A B)
digests() {
  local r
  for r in "${ROBOTS[@]}"; do field $r-a2 digest; field $r-gw digest; field $r-gw team_digest; done
}
converged() {
  local d; d=$(digests)
  [ "$(grep -c . <<<"$d")" = $((3 * ${#ROBOTS[@]})) ] && [ "$(sort -u <<<"$d" | wc -l)" = 1 ]
}
no_faults() {
  local n k
  for n in "$@"; do
    for k in equivocations divergences rejected; do
      [ "$(field $n $k)" = 0 ] || fail "$n: $k = $(field $n $k)"
    done
  done
}
gateway() {  # ROBOT: starts (or restarts) its gateway from its store; sets $started
  netns_run "$1" "$WORK/$1-gw.log" "$QUIVER" gateway --robot "$1" --name "$1-gw" --team "$WORK/team.json" --domain 0 \
    --team-loss-permille 200 --status-ms 100 --store "$WORK/store-$1-gw" --durability always
}
stay() {  # ROBOT: starts (or restarts) its agent that stays, from its store
  netns_run "$1" "$WORK/$1-a2.log" "$QUIVER" agent --name "$1-a2" --domain 0 --status-ms 100 \
    --store "$WORK/store-$1-a2" --durability always
}
counter() {  # ROBOT HZ: its counting agent (crash tests: prints "acked N", and "loaded N" on a restart)
  netns_run "$1" "$WORK/$1-c.log" "$QUIVER" agent --name "$1-c" --domain 0 --status-ms 100 \
    --store "$WORK/store-$1-c" --durability always --count-hz "$2"
}
last_acked() { grep -o '^acked [0-9]*' "$WORK/$1.log" | tail -1 | cut -d' ' -f2; }
last_loaded() { grep -o '^loaded [0-9]*' "$WORK/$1.log" | tail -1 | cut -d' ' -f2; }
acked_at_least() { [ "$(last_acked "$1")" -ge "$2" ]; }
restarted() { [ "$(grep -c '^loaded' "$WORK/$1.log")" -ge 2 ]; }
team_peers() { [ "$(field "$1-gw" team_peers)" = "$2" ]; }
declare -A gw
robot_up() {  # ROBOT
  gateway "$1"; gw[$1]=$started
  stay "$1"
}
settle() {  # WHAT: every running replica converges within 30 s
  local t0=$(date +%s%N)
  wait_until 30 converged || fail "$1: no convergence: $(digests | tr '\n' ' ')"
  echo "$1: converged $(( ($(date +%s%N) - t0) / 1000000 )) ms after the last writer stopped"
}
robot_up A
robot_up B
wait_until 15 team_peers A 1 || fail "the gateways did not meet on the team network"

# 1. Both robots write at once.
writer A A-w1; w1=$started; writer B B-w1; w2=$started
wait "$w1" "$w2"
settle "1. both robots wrote"

# 2. A's link is slow.
netns_slow A 256kbit || fail "tc tbf"
writer A A-w2; w1=$started
wait "$w1"
settle "2. robot A wrote over a 256 kbit/s link"
netns_fast A

# 3. B's gateway is killed; both robots write; B works alone; the gateway restarts and catches up.
kill -9 "${gw[B]}"
wait "${gw[B]}" 2>/dev/null
writer A A-w3; w1=$started; writer B B-w3; w2=$started
wait "$w1" "$w2"
[ "$(field B-a2 digest)" = "$(field B-w3 digest)" ] || fail "3. robot B's agents did not converge without their gateway"
echo "3. robot B's agents kept working without their gateway"
gateway B; gw[B]=$started
settle "3. robot B's gateway restarted"

# 4. All of robot B's processes crash at once while B counts and A writes; they restart from
# their stores.
counter B 20; c=$started
wait_until 15 acked_at_least B-c 20 || fail "4. B's counter acknowledged nothing"
writer A A-w4; w1=$started
sleep 0.5
for p in $(ip netns pids "$NS_TAG-B"); do kill -9 "$p" 2>/dev/null; done
acked=$(last_acked B-c)
wait "$w1"
gateway B; gw[B]=$started
stay B
counter B 0.0001
wait_until 15 restarted B-c || fail "4. B's counter did not restart"
loaded=$(last_loaded B-c)
[ "$loaded" -ge "$acked" ] || fail "4. B's counter acknowledged $acked but reloaded $loaded"
equal_counter() { [ "$(field B-c digest)" = "$(field B-a2 digest)" ]; }
settle "4. all of robot B's processes were killed and restarted from their stores (acknowledged $acked, reloaded $loaded)"
wait_until 10 equal_counter || fail "4. B's counter did not converge with B's other agent"

# 5. Robot C joins late.
ROBOTS=(A B C)
robot_up C
settle "5. robot C joined late"

# 6. Robot C leaves for good.
kill -TERM "${gw[C]}"
wait "${gw[C]}"
wait_until 10 team_peers A 1 || fail "6. robot A still counts C's gateway: $(field A-gw team_peers) team peers"
wait_until 10 team_peers B 1 || fail "6. robot B still counts C's gateway: $(field B-gw team_peers) team peers"
echo "6. robot C left; A and B see one other gateway each"
no_faults A-a2 B-a2 B-c C-a2 A-gw B-gw
echo PASS
