#!/usr/bin/env bash
# Locks across robots with real processes: two robots, each a network namespace of its own
# (scripts/netns.sh) with its gateway and an agent that competes for the lock of the mug
# (`quiver agent --contend mug`: hold 100 ms, release, claim again; each hold printed as
# "held START END" on the monotonic clock the namespaces share). Checks, over 8 s of contention:
# both robots' agents hold the lock several times, at most a quarter of the holds end before their
# time (two claims racing: one is told it lost), and no hold of one overlaps a hold of the other.
# Without the gateways' hold queries and member lists, each robot sees the other's holder as gone
# and claims at once: nearly every hold is cut short, and holds overlap.
# Usage: gateway_locks_netns_test.sh QUIVER WORLD   (exit 77: skipped without root, see netns.sh)
set -uo pipefail
QUIVER=$1
WORLD=$2
. "$(dirname "$0")/gateway_lib.sh"
team_up A B
team_peers() { [ "$(field A-gw team_peers)" = 1 ] && [ "$(field B-gw team_peers)" = 1 ]; }
for r in A B; do
  netns_run $r "$WORK/$r-gw.log" "$QUIVER" gateway --robot $r --name $r-gw --team "$WORK/team.json" --domain 0 --status-ms 100
done
wait_until 15 team_peers || fail "the gateways did not meet on the team network"
echo "the gateways met on the team network"
for r in A B; do
  netns_run $r "$WORK/$r-c.log" "$QUIVER" agent --name $r-c --domain 0 --world "$WORLD" --contend mug --hold-ms 100 \
    --run-for 10 --status-ms 200
  pids+=("$started")
done
wait "${pids[@]}"
holds() { grep -c '^held ' "$WORK/$1-c.log"; }
echo "holds: A $(holds A), B $(holds B)"
[ "$(holds A)" -ge 3 ] && [ "$(holds B)" -ge 3 ] || fail "a robot's agent seldom held the lock: A $(holds A), B $(holds B)"
# Every pair of holds from the two robots: one ends before the other starts.
overlaps=$(
  { sed -n 's/^held \([0-9]*\) \([0-9]*\)$/\1 \2 A/p' "$WORK/A-c.log"; sed -n 's/^held \([0-9]*\) \([0-9]*\)$/\1 \2 B/p' "$WORK/B-c.log"; } |
    sort -n | awk '{ if (NR > 1 && $1 < end && $3 != who) { n++; print "overlap: " who " until " end ", " $3 " from " $1 > "/dev/stderr" }
                     if ($2 > end) { end = $2; who = $3 } } END { print n + 0 }'
)
[ "$overlaps" = 0 ] || fail "$overlaps holds overlapped a hold of the other robot"
# A hold may end early when two claims race (both claim as the other releases: one is told it
# lost), rarely; without the gateways' hold queries nearly every hold is cut short.
for r in A B; do
  lost=$(field $r-c holds_lost)
  [ $((lost * 4)) -le "$(holds $r)" ] || fail "$r: $lost of $(holds $r) holds were lost before their time"
done
for n in A-gw B-gw; do
  for k in equivocations divergences rejected; do
    [ "$(field $n $k)" = 0 ] || fail "$n: $k = $(field $n $k)"
  done
done
echo "lost early: A $(field A-c holds_lost), B $(field B-c holds_lost); no hold overlapped a hold of the other robot"
echo PASS
