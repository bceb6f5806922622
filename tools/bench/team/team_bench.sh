#!/usr/bin/env bash
# quiver bench team (issue 23, docs/teams.md "Traffic between robots"): robots as network
# namespaces the benchmark makes itself (scripts/netns.sh; root only; nothing outside them), each
# with its gateway (`quiver gateway`: the robot's loopback domain 0 and the team domain 7 on its
# veth). `quiver bench team` embeds this script and netns.sh and runs them with its own path.
#  1. Tracking: robot R0 runs the human tracker (`quiver run humans`: 2 people x 15 joints x 30 Hz,
#     900 pose updates/s); every other robot runs an agent that measures how fresh the joints are
#     when they reach it (`quiver run rooms --measure-humans`). Measured: the bytes all robots send
#     on the team network while the tracker runs (veth tx_bytes, minus the idle rate measured
#     before it started) against the delta bytes the tracker publishes (its `published_bytes`):
#     target ratio <= 1.5 x (robots - 1); the joints' latency to the other robots: p99 <= 20 ms.
#  2. Join: R0 holds a world of NODES nodes x 10 attributes; the last robot joins late (its
#     gateway and one agent start together): the time until its agent holds R0's state, <= 1 s.
# Prints one JSON line; exits 0 when every target is met, 1 when one is not, 77 without root.
# Usage: team_bench.sh QUIVER [--robots R=3] [--seconds S=10] [--nodes N=10000] [--out DIR]
set -uo pipefail
QUIVER=$1
shift
ROBOTS=3 SECS=10 NODES=10000 OUT=""
while [ $# -gt 0 ]; do
  case $1 in
    --robots) ROBOTS=$2; shift 2 ;;
    --seconds) SECS=$2; shift 2 ;;
    --nodes) NODES=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    *) echo "team_bench.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
. "$(dirname "$0")/netns.sh"
QV_NS_PREFIX=qvb NS_TAG="qvb-$$"
netns_require
if [ -n "$OUT" ]; then WORK=$OUT; mkdir -p "$WORK" && rm -f "$WORK"/*.log; else WORK=$(mktemp -d); fi
trap 'netns_cleanup; [ -n "$OUT" ] || rm -rf "$WORK"' EXIT
say() { echo "bench team: $*" >&2; }
die() { say "$*"; for f in "$WORK"/*.log; do echo "--- $f" >&2; grep -v '^{' "$f" | tail -5 >&2; done; exit 1; }
names=()
for ((i = 0; i < ROBOTS; ++i)); do names+=("R$i"); done
netns_up "${names[@]}" || die "could not build the namespaces"
netns_team_file "$WORK/team.json" "${names[@]}"
last_of() { grep '^{' "$WORK/$1.log" 2>/dev/null | tail -1; }
field() { last_of "$1" | grep -o "\"$2\":[^,}]*" | head -1 | cut -d: -f2 | tr -d '"'; }  # NAME KEY
wait_until() {  # TIMEOUT_S CMD...: polls every 50 ms
  local i; for ((i = 0; i < $1 * 20; ++i)); do "${@:2}" 2>/dev/null && return 0; sleep 0.05; done; return 1
}
tx_total() { local r s=0; for r in "${names[@]}"; do s=$((s + $(netns_tx_bytes "$r"))); done; echo $s; }
now_ns() { date +%s%N; }
stop_all() { local p; for p in "${NS_PIDS[@]}"; do kill -TERM "$p" 2>/dev/null; done; wait 2>/dev/null; NS_PIDS=(); }
gateway() { netns_run "$1" "$WORK/$1-gw.log" "$QUIVER" gateway --robot "$1" --team "$WORK/team.json" --domain 0 --status-ms 100; }
gateways_meet() {  # ROBOT...: each gateway sees the others on the team network
  local r; for r in "$@"; do [ "$(field "$r-gw" team_peers)" = $(($# - 1)) ] || return 1; done
}

# 1. Tracking.
for r in "${names[@]}"; do gateway "$r"; done
for r in "${names[@]:1}"; do
  netns_run "$r" "$WORK/rooms-$r.log" "$QUIVER" run rooms --name "rooms-$r" --domain 0 --measure-humans --status-ms 500
done
wait_until 20 gateways_meet "${names[@]}" || die "the gateways did not meet on the team network"
say "$ROBOTS gateways met on the team network; measuring the idle traffic"
sleep 3
t0=$(now_ns); b0=$(tx_total); sleep 4; t1=$(now_ns); b1=$(tx_total)
idle_rate=$(( (b1 - b0) * 1000000000 / (t1 - t0) ))
netns_run R0 "$WORK/humans.log" "$QUIVER" run humans --domain 0 --status-ms 500 --run-for "$(python3 -c "print($SECS + 1)")" --hand-over 0
tracker=$started
t0=$(now_ns); b0=$(tx_total)
wait "$tracker"
t1=$(now_ns); b1=$(tx_total)
sleep 0.5
stop_all
dt_ns=$((t1 - t0))
published=$(field humans published_bytes)
rt_updates=$(field humans rt_updates)
[ -n "$published" ] && [ "$published" -gt 0 ] || die "the tracker published nothing"
team_bytes=$(( b1 - b0 - idle_rate * dt_ns / 1000000000 ))
# The joints' freshness at every other robot: their latency probes' histograms (10 us buckets),
# pooled; a bucket counts as its upper edge.
read -r poses p50_us p99_us < <(for r in "${names[@]:1}"; do last_of "rooms-$r"; done | python3 -c '
import json, sys
hist = {}
for line in sys.stdin:
    for k, v in json.loads(line).get("humans_latency", {}).get("hist_10us", {}).items():
        hist[int(k)] = hist.get(int(k), 0) + v
n = sum(hist.values())
def pct(q):
    seen = 0
    for k in sorted(hist):
        seen += hist[k]
        if seen >= q * n:
            return (k + 1) * 10
    return 0
print(n, pct(0.5), pct(0.99))')
[ "${poses:-0}" -gt 0 ] || die "no other robot saw a joint"
say "tracking: $published delta bytes published, $team_bytes bytes on the team network ($idle_rate B/s idle)"

# 2. Join.
python3 - "$NODES" >"$WORK/world.json" <<'EOF'
import json, sys
n = int(sys.argv[1])
nodes = [{"name": "world", "type": "world"}] + [
    {"name": f"n{i}", "type": "thing", "attrs": {f"a{k}": i * 10 + k for k in range(10)}} for i in range(n)]
json.dump({"quiver_world": 1, "nodes": nodes, "edges": []}, sys.stdout)
EOF
last=${names[$((ROBOTS - 1))]}
held=("${names[@]:0:$((ROBOTS - 1))}")
for r in "${held[@]}"; do gateway "$r"; done
netns_run R0 "$WORK/holder.log" "$QUIVER" agent --name holder --domain 0 --world "$WORK/world.json" --status-ms 100
team_has_world() {
  local d r; d=$(field holder digest); [ -n "$d" ] && [ "$(field holder nodes)" -gt "$NODES" ] || return 1
  for r in "${held[@]}"; do [ "$(field "$r-gw" team_digest)" = "$d" ] || return 1; done
}
wait_until 60 gateways_meet "${held[@]}" || die "the gateways did not meet again"
wait_until 60 team_has_world || die "the world did not reach the team network"
sleep 1
say "$(field holder nodes) nodes on the team network; robot $last joins"
t0=$(now_ns)
gateway "$last"
netns_run "$last" "$WORK/late.log" "$QUIVER" agent --name late --domain 0 --status-ms 20
joined() { [ "$(field late digest)" = "$(field holder digest)" ]; }
if wait_until 30 joined; then join_ms=$(( ($(now_ns) - t0) / 1000000 )); else join_ms=-1; fi
stop_all

ratio=$(python3 -c "print(round($team_bytes / (($ROBOTS - 1) * $published), 3))")
secs=$(python3 -c "print(round($dt_ns / 1e9, 2))")
ok=$(python3 -c "print('true' if $ratio <= 1.5 and $p99_us <= 20000 and 0 <= $join_ms <= 1000 else 'false')")
echo "{\"bench\":\"team\",\"robots\":$ROBOTS,\"seconds\":$secs,\"tracker_rt_updates\":${rt_updates:-0},\"tracker_published_bytes\":$published,\"team_bytes\":$team_bytes,\"idle_team_bytes_per_s\":$idle_rate,\"team_bytes_per_published_byte_per_other_robot\":$ratio,\"ratio_limit\":1.5,\"joint_poses_received\":$poses,\"joints_latency_us_p50\":$p50_us,\"joints_latency_us_p99\":$p99_us,\"p99_limit_us\":20000,\"join_nodes\":$NODES,\"join_ms\":$join_ms,\"join_limit_ms\":1000,\"ok\":$ok}"
[ "$ok" = true ]
