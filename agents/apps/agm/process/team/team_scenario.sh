#!/usr/bin/env bash
# quiver scenario team (issue 23, docs/teams.md "The team scenario"): robots as network namespaces
# the scenario makes itself (scripts/netns.sh; root only; nothing is sent outside them). Each robot
# runs its gateway and its agents as processes on its own loopback domain 0, each with a store
# (--durability always): navigation, rooms, grasping, its planner, the human tracker on robot A,
# idle agents up to --agents-per-robot; the hands share one custody directory. Mid-task the team
# link is cut (every robot unplugged at the switch) and healed, and one robot crashes (SIGKILL of
# all its processes) and comes back from its stores. `quiver scenario team` embeds this script,
# runs it, then checks what the processes wrote (their JSON lines) and the final graph.
# Writes into --out: one log per process (ROBOT-ROLE.log), faults.log (monotonic ns and what),
# final.json (the graph of robot A's domain at the end), team_bytes (bytes all robots sent on
# the team network). Exits 0 once the run is over (the checks are the caller's), 1 when it could
# not run, 77 without root.
# Usage: team_scenario.sh QUIVER --out DIR [--robots R=2] [--agents-per-robot A=6]
#        [--partition-at S --heal-at S] [--crash ROBOT@S] [--limit S=120]
set -uo pipefail
QUIVER=$1
shift
ROBOTS=2 PER=6 PART_AT="" HEAL_AT="" CRASH="" OUT="" LIMIT=120
while [ $# -gt 0 ]; do
  case $1 in
    --robots) ROBOTS=$2; shift 2 ;;
    --agents-per-robot) PER=$2; shift 2 ;;
    --partition-at) PART_AT=$2; shift 2 ;;
    --heal-at) HEAL_AT=$2; shift 2 ;;
    --crash) CRASH=$2; shift 2 ;;
    --limit) LIMIT=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    *) echo "team_scenario.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -n "$OUT" ] || { echo "team_scenario.sh: --out is required" >&2; exit 2; }
. "$(dirname "$0")/netns.sh"
QV_NS_PREFIX=qvs NS_TAG="qvs-$$"
netns_require
WORK=$OUT
mkdir -p "$WORK" && rm -rf "$WORK"/*.log "$WORK"/store "$WORK"/custody "$WORK"/final.json "$WORK"/team_bytes
say() { echo "scenario team: $*" >&2; }
die() { say "$*"; exit 1; }
now_ns() { python3 -c 'import time; print(time.monotonic_ns())'; }
mark() { echo "$(now_ns) $*" >>"$WORK/faults.log"; say "$*"; }  # a fault, stamped on the agents' clock
: >"$WORK/faults.log"
names=()
for ((i = 0; i < ROBOTS; ++i)); do names+=("$(printf "\\x$(printf %x $((65 + i)))")"); done
netns_up "${names[@]}" || die "could not build the namespaces"
netns_team_file "$WORK/team.json" "${names[@]}"
last_of() { grep '^{"' "$WORK/$1.log" 2>/dev/null | grep '"name"' | tail -1; }
field() { last_of "$1" | grep -o "\"$2\":[^,}]*" | head -1 | cut -d: -f2 | tr -d '"'; }  # PROC KEY
wait_until() {  # TIMEOUT_S CMD...: polls every 100 ms
  local i; for ((i = 0; i < $1 * 10; ++i)); do "${@:2}" 2>/dev/null && return 0; sleep 0.1; done; return 1
}
declare -A PIDS=()  # robot -> its processes' pids
common=(--domain 0 --status-ms 250 --durability always)
start_robot() {  # ROBOT: its gateway and agents, each with its store (a restart reloads it)
  local r=$1 role k idle=1 pids=""
  netns_run "$r" "$WORK/$r-gateway.log" "$QUIVER" gateway --robot "$r" --team "$WORK/team.json" --domain 0 \
    --status-ms 250 --store "$WORK/store/$r-gateway" --durability always
  pids+=" $started"
  for role in navigation rooms grasping agm-planner; do
    local name=$r-${role#agm-}
    local probe=()  # the joints tracked on robot A, measured where they arrive
    [ "$role" = rooms ] && [ "$r" != A ] && probe=(--measure-humans)
    [ "$role" = navigation ] && probe=(--quiet-when-done)  # no more poses once the plan is achieved
    netns_run "$r" "$WORK/$name.log" "$QUIVER" run "$role" --name "$name" --team-robot "$r" --robots "$ROBOTS" \
      --custody "$WORK/custody" --store "$WORK/store/$name" "${probe[@]}" "${common[@]}"
    pids+=" $started"
  done
  for ((k = 5; k < PER; ++k)); do
    if [ "$r" = A ] && [ $k = 5 ]; then
      netns_run "$r" "$WORK/A-humans.log" "$QUIVER" run humans --name A-humans --team-robot A --robots "$ROBOTS" \
        --store "$WORK/store/A-humans" "${common[@]}"
    else
      netns_run "$r" "$WORK/$r-idle$idle.log" "$QUIVER" agent --name "$r-idle$idle" --store "$WORK/store/$r-idle$idle" \
        "${common[@]}"
      idle=$((idle + 1))
    fi
    pids+=" $started"
  done
  PIDS[$r]=$pids
}
crash_robot() {  # ROBOT: SIGKILL of all its processes at once
  local p; for p in ${PIDS[$1]}; do kill -9 "$p" 2>/dev/null; done
  for p in ${PIDS[$1]}; do wait "$p" 2>/dev/null; done  # reaped quietly
}
gateways_meet() {
  local r; for r in "${names[@]}"; do [ "$(field "$r-gateway" team_peers)" = $((ROBOTS - 1)) ] || return 1; done
}
achieved() {  # every robot's planner says its plan is achieved
  local r; for r in "${names[@]}"; do last_of "$r-planner" | grep -q '"planner":"achieved"' || return 1; done
}
even_digest() {  # the one digest every gateway holds on both sides (latest status lines), or fail
  local r d first=""
  for r in "${names[@]}"; do
    [ "$(field "$r-gateway" even)" = true ] || return 1
    d=$(field "$r-gateway" digest)
    [ -n "$d" ] && [ "${first:-$d}" = "$d" ] || return 1
    first=$d
  done
  echo "$first"
}
settled() {  # the team holds one state, and it has not changed for two status periods
  local a b
  a=$(even_digest) || return 1
  sleep 0.6
  b=$(even_digest) && [ "$a" = "$b" ]
}
tx_total() { local r s=0; for r in "${names[@]}"; do s=$((s + $(netns_tx_bytes "$r"))); done; echo $s; }

b0=$(tx_total)
for r in "${names[@]}"; do start_robot "$r"; done
mark "start: $ROBOTS robots x $PER processes (gateway, navigation, rooms, grasping, planner, humans on A, idle)"
t0=$SECONDS
wait_until 30 gateways_meet || die "the gateways did not meet on the team network"
say "the gateways met on the team network"
crash_robot_name=${CRASH%@*} crash_at=${CRASH#*@}
cut_done=0 heal_done=0 crash_done=0 back_done=0
while (( SECONDS - t0 < LIMIT )); do
  el=$((SECONDS - t0))
  if [ -n "$PART_AT" ] && [ $cut_done = 0 ] && (( el >= ${PART_AT%.*} )); then
    for r in "${names[@]}"; do netns_cut "$r"; done
    mark "cut: the team link is down (every robot unplugged at the switch)"; cut_done=1
  fi
  if [ -n "$HEAL_AT" ] && [ $cut_done = 1 ] && [ $heal_done = 0 ] && (( el >= ${HEAL_AT%.*} )); then
    for r in "${names[@]}"; do netns_heal "$r"; done
    mark "heal: the team link is up"; heal_done=1
  fi
  if [ -n "$CRASH" ] && [ $crash_done = 0 ] && (( el >= ${crash_at%.*} )); then
    crash_robot "$crash_robot_name"
    mark "crash: robot $crash_robot_name (SIGKILL of its gateway and agents)"; crash_done=1; crash_t=$SECONDS
  fi
  if [ $crash_done = 1 ] && [ $back_done = 0 ] && (( SECONDS - crash_t >= 2 )); then
    start_robot "$crash_robot_name"
    mark "restart: robot $crash_robot_name (every process from its store)"; back_done=1
  fi
  faults_over=1
  [ -n "$PART_AT" ] && [ $heal_done = 0 ] && faults_over=0
  [ -n "$CRASH" ] && [ $back_done = 0 ] && faults_over=0
  if [ $faults_over = 1 ] && achieved; then break; fi
  sleep 0.2
done
(( SECONDS - t0 < LIMIT )) && mark "done: every robot's plan is achieved" || mark "limit: ${LIMIT} s passed"
sleep 2
b1=$(tx_total)
echo $((b1 - b0)) >"$WORK/team_bytes"
# Quiet: the tracker stops; the replicas settle; the final graph as robot A's domain holds it.
kill -TERM $(pgrep -f -- "--name A-humans" | head -1) 2>/dev/null
# A robot may still be driving when the plans are achieved (its mission done by another robot
# while it went for the mug): the checks are made once nothing changes any more, or after 30 s.
sleep 1
settle_by=$((SECONDS + 30)) calm=0
while (( SECONDS < settle_by )); do settled && { calm=1; break; }; sleep 0.1; done
if [ $calm = 1 ]; then mark "settled: every gateway even, one state across the team"
else mark "not settled after 30 s: the replicas are compared as they are"; fi
ip netns exec "$NS_TAG-A" "$QUIVER" dump --domain 0 --json --timeout 20 >"$WORK/final.json" 2>"$WORK/dump.log" ||
  say "could not dump the final graph (dump.log)"
for r in "${names[@]}"; do for p in ${PIDS[$r]}; do kill -TERM "$p" 2>/dev/null; done; done
wait 2>/dev/null
NS_PIDS=()
mark "stopped: every process exited"
exit 0
