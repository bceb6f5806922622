#!/usr/bin/env bash
# Two robots on a team network, each a network namespace of its own (scripts/netns.sh): on
# each, an agent that stays (X-a2), short-lived writers, and the gateway (`quiver gateway`: the
# robot's loopback domain 0 and the team domain 7 on its veth). Checks:
#  1. a change made on robot A reaches robot B's agent, through both gateways;
#  2. with the team link cut at the bridge, both robots write: each robot converges on its own;
#  3. after the link is back, every replica (both agents, both sides of both gateways) holds one
#     state, with no equivocation, divergence or rejected sample;
#  and `quiver view` on robot B names robot A's agent with its robot, lists robot A as reachable
#  while the link is up, and no longer while it is cut.
# Usage: gateway_netns_test.sh QUIVER   (exit 77: skipped without root, see netns.sh)
set -uo pipefail
QUIVER=$1
. "$(dirname "$0")/gateway_lib.sh"
team_up A B
digests() { for n in A-a2 B-a2 A-gw B-gw; do field $n digest; done; field A-gw team_digest; field B-gw team_digest; }
converged() { local d; d=$(digests); [ "$(grep -c . <<<"$d")" = 6 ] && [ "$(sort -u <<<"$d" | wc -l)" = 1 ]; }
alone() { [ "$(field A-a2 digest)" = "$(field A-gw digest)" ] && [ "$(field B-a2 digest)" = "$(field B-gw digest)" ]; }
team_peers() { [ "$(field A-gw team_peers)" = "$1" ] && [ "$(field B-gw team_peers)" = "$1" ]; }
for r in A B; do
  netns_run $r "$WORK/$r-gw.log" "$QUIVER" gateway --robot $r --name $r-gw --team "$WORK/team.json" --domain 0 --status-ms 100
  netns_run $r "$WORK/$r-a2.log" "$QUIVER" agent --name $r-a2 --domain 0 --status-ms 100
done
netns_run B "$WORK/B-view.log" "$QUIVER" view --domain 0 --listen 127.0.0.1:8093
# The agents robot B's viewer lists (`quiver view`'s /api/info), as NAME@ROBOT, remote ones with "+".
view_agents() {
  ip netns exec "$NS_TAG-B" python3 -c '
import json, urllib.request
info = json.load(urllib.request.urlopen("http://127.0.0.1:8093/api/info", timeout=2))
print(" ".join(sorted(("+" if a.get("remote") else "") + a["name"] + "@" + a.get("robot", "")
                      for a in info["agents"] if a["alive"])))'
}
sees() { view_agents | tr ' ' '\n' | grep -qx -- "$1"; }
# The writers robot B's viewer names in its inspector (`/api/snapshot`: every attribute value's).
view_writers() {
  ip netns exec "$NS_TAG-B" python3 -c '
import json, urllib.request
snap = json.load(urllib.request.urlopen("http://127.0.0.1:8093/api/snapshot", timeout=2))
print("\n".join(sorted({v["writer"] for n in snap["nodes"] for a in n["attrs"] for v in a["values"]})))'
}
wait_until 15 team_peers 1 || fail "the gateways did not meet on the team network"
echo "the gateways met on the team network"

# 1. A change on A reaches B.
writer A A-a1; w=$started
wait "$w"
wait_until 15 converged || fail "A's changes did not reach B: $(digests | tr '\n' ' ')"
[ "$(field B-a2 nodes)" -gt 0 ] || fail "B holds no node"
echo "1. robot A's changes reached robot B: $(field B-a2 nodes) nodes, $(field A-gw deltas_to_team) deltas crossed"
wait_until 10 sees "+A-a2@A" || fail "robot B's viewer does not name robot A's agent A-a2 on robot A: $(view_agents)"
sees "B-a2@B" || fail "robot B's viewer does not list its own agent B-a2 on robot B: $(view_agents)"
echo "   robot B's viewer lists: $(view_agents)"
# A-a1 wrote on robot A and has left: B's viewer still names it, with its robot.
wait_until 10 eval 'view_writers | grep -qx "A-a1 @ A"' || fail "robot B's viewer does not name the writer A-a1 @ A: $(view_writers | tr '\n' ' ')"
echo "   robot B's viewer names the writers: $(view_writers | tr '\n' ' ')"

# 2. The team link is cut: both robots write; each converges on its own; the robots differ.
netns_cut A
wait_until 10 team_peers 0 || fail "the gateways did not notice the cut"
wait_until 10 eval '! sees "+A-a2@A"' || fail "robot B's viewer still lists robot A as reachable: $(view_agents)"
echo "   cut off, robot B's viewer lists: $(view_agents)"
writer A A-p; wa=$started; writer B B-p; wb=$started
wait "$wa" "$wb"
wait_until 10 alone || fail "a robot did not converge on its own while cut off: $(digests | tr '\n' ' ')"
[ "$(field A-a2 digest)" != "$(field B-a2 digest)" ] || fail "the robots did not differ while cut off"
echo "2. cut off, each robot converged on its own"

# 3. The link is back: everything converges.
t0=$(date +%s%N)
netns_heal A
wait_until 30 converged || fail "no convergence after the heal: $(digests | tr '\n' ' ')"
echo "3. converged $(( ($(date +%s%N) - t0) / 1000000 )) ms after the heal; team network bytes sent by A: $(netns_tx_bytes A), B: $(netns_tx_bytes B)"
for n in A-a2 B-a2 A-gw B-gw; do
  for k in equivocations divergences rejected; do
    [ "$(field $n $k)" = 0 ] || fail "$n: $k = $(field $n $k)"
  done
done
echo PASS
