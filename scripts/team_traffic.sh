#!/usr/bin/env bash
# Traffic between robots (docs/teams.md), measured with real processes in network namespaces the
# script makes itself (scripts/netns.sh; root only, nothing outside them): R robots, each
# with A idle agents; one writer on the first robot makes changes at HZ for S seconds. Two
# topologies, the same workload:
#   gateways: the agents on each robot's own loopback domain, one `quiver gateway` per robot;
#   flat:     every agent directly in one team domain on the robots' network (unicast peers).
# Prints one JSON line per topology: the bytes all robots sent on the team network while the
# writer ran (veth tx_bytes, minus the idle rate measured before), per change and per second.
# Usage: scripts/team_traffic.sh QUIVER [ROBOTS=3] [AGENTS=3] [HZ=20] [SECONDS=10]
set -uo pipefail
QUIVER=$1 ROBOTS=${2:-3} AGENTS=${3:-3} HZ=${4:-20} SECS=${5:-10}
. "$(dirname "$0")/netns.sh"
QV_NS_PREFIX=qvb NS_TAG="qvb-$$"
netns_require
WORK=$(mktemp -d)
trap 'netns_cleanup; rm -rf "$WORK"' EXIT
names=()
for ((i = 0; i < ROBOTS; ++i)); do names+=("R$i"); done
netns_up "${names[@]}" || { echo "could not build the namespaces" >&2; exit 1; }
netns_team_file "$WORK/team.json" "${names[@]}"
tx_total() { local r s=0; for r in "${names[@]}"; do s=$((s + $(netns_tx_bytes "$r"))); done; echo $s; }
now_ns() { date +%s%N; }
measure() {  # TOPOLOGY: after the processes settled: idle rate, then the writer's run
  sleep 6
  local t0 b0 t1 b1
  t0=$(now_ns); b0=$(tx_total); sleep 5; t1=$(now_ns); b1=$(tx_total)
  local idle_rate=$(( (b1 - b0) * 1000000000 / (t1 - t0) ))
  netns_run R0 "$WORK/writer.log" "$QUIVER" agent --name writer --domain "$DOMAIN" "${DDS[@]}" --churn-hz "$HZ" \
    --churn-for "$SECS" --run-for $((SECS + 3)) --hand-over 0 --status-ms 200
  local w=$started
  t0=$(now_ns); b0=$(tx_total)
  wait "$w"
  t1=$(now_ns); b1=$(tx_total)
  local dt_ns=$((t1 - t0)) changes
  changes=$(grep '^{' "$WORK/writer.log" | tail -1 | grep -o '"published":[0-9]*' | cut -d: -f2)
  local bytes=$(( b1 - b0 - idle_rate * dt_ns / 1000000000 ))
  # Every agent of every robot ends with the writer's state.
  local f d converged=false
  for ((i = 0; i < 50; ++i)); do
    sleep 0.2
    d=$(for f in "$WORK"/R*-a*.log "$WORK/writer.log"; do grep '^{' "$f" | tail -1 | grep -o '"digest":"[0-9a-f]*"'; done | sort -u | wc -l)
    [ "$d" = 1 ] && converged=true && break
  done
  echo "{\"topology\":\"$1\",\"converged\":$converged,\"robots\":$ROBOTS,\"agents_per_robot\":$AGENTS,\"changes\":${changes:-0},\"seconds\":$(echo "scale=2; $dt_ns / 1000000000" | bc),\"team_bytes\":$bytes,\"team_bytes_per_change\":$(( bytes / ${changes:-1} )),\"idle_team_bytes_per_s\":$idle_rate}"
  netns_cleanup_procs
  rm -f "$WORK"/R*-a*.log "$WORK/writer.log"
}
netns_cleanup_procs() { local p; for p in "${NS_PIDS[@]}"; do kill -TERM "$p" 2>/dev/null; done; wait 2>/dev/null; NS_PIDS=(); }

# 1. Gateways.
DOMAIN=0 DDS=()
for r in "${names[@]}"; do
  netns_run "$r" "$WORK/$r-gw.log" "$QUIVER" gateway --robot "$r" --team "$WORK/team.json" --domain 0
  for ((a = 0; a < AGENTS; ++a)); do netns_run "$r" "$WORK/$r-a$a.log" "$QUIVER" agent --name "$r-a$a" --domain 0 --status-ms 200; done
done
measure gateways

# 2. Every agent in one team domain.
DOMAIN=7
for r in "${names[@]}"; do
  "$QUIVER" gateway --robot "$r" --team "$WORK/team.json" --print-team-config |
    sed "s|<MaxAutoParticipantIndex>[0-9]*<|<MaxAutoParticipantIndex>$((AGENTS + 2))<|" >"$WORK/$r.xml"
done
for r in "${names[@]}"; do
  for ((a = 0; a < AGENTS; ++a)); do
    netns_run "$r" "$WORK/$r-a$a.log" "$QUIVER" agent --name "$r-a$a" --domain 7 --dds-config "$WORK/$r.xml" --status-ms 200
  done
done
DDS=(--dds-config "$WORK/R0.xml")
measure flat
