#!/usr/bin/env bash
# DDS Security on the team domain (docs/teams.md): robots A and B hold the team CA's credentials
# for their gateways (`quiver gateway --team-security DIR`); a change made on A reaches B. Host C,
# on the same team network and listed in the team file, is an intruder: first without any
# credentials, then with credentials of another CA. Either way, its gateway meets no other
# gateway, nothing its robot writes reaches A or B, and nothing of A's or B's reaches it.
# Usage: gateway_security_netns_test.sh QUIVER   (exit 77: skipped without root, see netns.sh)
set -uo pipefail
QUIVER=$1
. "$(dirname "$0")/gateway_lib.sh"
team_up A B C
"$QUIVER" keys init "$WORK/team-keys" >/dev/null || fail "keys init"
"$QUIVER" keys init "$WORK/other-keys" >/dev/null || fail "keys init (another CA)"
for r in A B; do "$QUIVER" keys add-agent "$r-gw.team" --dir "$WORK/team-keys" >/dev/null || fail "keys add-agent"; done
"$QUIVER" keys add-agent "C-gw.team" --dir "$WORK/other-keys" >/dev/null || fail "keys add-agent (another CA)"
gateway() {  # ROBOT [--team-security DIR]; sets $started
  local r=$1; shift
  netns_run "$r" "$WORK/$r-gw.log" "$QUIVER" gateway --robot "$r" --name "$r-gw" --team "$WORK/team.json" --domain 0 \
    --status-ms 100 "$@"
}
same() { [ -n "$(field "$1" "$2")" ] && [ "$(field "$1" "$2")" = "$(field "$3" "$4")" ]; }
team_peers() { [ "$(field "$1-gw" team_peers)" = "$2" ]; }
for r in A B; do
  gateway $r --team-security "$WORK/team-keys"
  netns_run $r "$WORK/$r-a2.log" "$QUIVER" agent --name "$r-a2" --domain 0 --status-ms 100
done
netns_run C "$WORK/C-a2.log" "$QUIVER" agent --name C-a2 --domain 0 --status-ms 100
wait_until 20 team_peers A 1 || fail "the secured gateways did not meet on the team network"
writer A A-w1; w=$started
wait "$w"
wait_until 15 same A-a2 digest B-a2 digest || fail "A's changes did not reach B over the secured team domain"
echo "1. a change crossed the secured team domain: $(field B-a2 nodes) nodes on B"

intruder() {  # WHAT [--team-security DIR]: C's gateway joins as WHAT, C writes; nobody hears it
  local what=$1; shift
  gateway C "$@"; local g=$started
  writer C "C-w-$what"; local w=$started
  wait "$w"
  sleep 3  # a lease and more for discovery to have happened if it could
  [ "$(field C-gw team_peers)" = 0 ] || fail "$what: the intruder's gateway met $(field C-gw team_peers) gateways"
  [ "$(field A-gw team_peers)" = 1 ] && [ "$(field B-gw team_peers)" = 1 ] ||
    fail "$what: A and B count $(field A-gw team_peers) and $(field B-gw team_peers) team peers"
  same A-a2 digest B-a2 digest || fail "$what: A and B differ"
  ! same A-a2 digest C-a2 digest || fail "$what: C's changes reached A (or A's reached C)"
  [ "$(field C-gw deltas_to_team)" -gt 0 ] || fail "$what: C's gateway sent nothing to the team (the check would be empty)"
  [ "$(field C-gw deltas_to_robot)" = 0 ] || fail "$what: C's gateway received $(field C-gw deltas_to_robot) deltas"
  kill -TERM "$g"; wait "$g"
  echo "2. an intruder $what: met nobody, its $(field C-gw deltas_to_team) deltas reached nobody, it received none"
}
intruder "without credentials"
intruder "with another CA's credentials" --team-security "$WORK/other-keys"
echo PASS
