#!/usr/bin/env bash
# Crash tests of the durable store during a large state transfer, with real agent processes over
# Cyclone DDS on loopback (docs/persistence.md). Usage: state_transfer_crash_test.sh QUIVER [SEED]
# (STATE_NODES=N sets the size of the world, default 60000 nodes, about 20 MB of state).
#
# Agent "big" holds a large world in its store (batch); it is restarted from its store first, so
# its relay buffer is empty and a newcomer's pull is answered with its whole state, in chunks.
# Agent "joinerR" (R: the round) starts with an empty store (always) and counts at 200 Hz,
# printing "acked N". Each round's joiner has a name of its own: its counter node is
# "joinerR.counter", and a joiner whose setup ran before big's state arrived would otherwise make
# a second "joiner.counter" beside an earlier round's, and reload the wrong one.
#
#  1. The joiner is killed with SIGKILL while it receives the state (or, when the kill comes
#     later, while its store compacts the state it just wrote: it compacts every 10 KiB), then
#     restarted from its store: the store must load (the count it reloads is at least the last
#     one acknowledged), the joiner pulls the state again, and the two replicas end equal.
#  2. The sender is killed with SIGKILL while the joiner receives its state; it is restarted
#     from its store, the joiner pulls again, and the replicas end equal (the joiner's
#     acknowledged counts included).
#  3. Both are killed at once during a transfer and restarted: same checks.
# Every kill prints where it landed, read from the agents' last status lines (20 ms apart):
# mid-transfer (the joiner's pull is out, no state applied yet), mid-compaction (the state is
# applied, the first compaction has not finished), or after.
set -uo pipefail
QUIVER=$1
SEED=${2:-$(( $(date +%s) % 100000 ))}
NODES=${STATE_NODES:-60000}
echo "state_transfer_crash_test seed $SEED, $NODES nodes (replay: $0 $QUIVER $SEED)"
RANDOM=$SEED
WORK=$(mktemp -d)
DOMAIN=$(( 200 + SEED % 30 ))
. "$(dirname "$0")/crash_lib.sh"
# field LOG NAME: NAME's value in LOG's last status line.
field() { grep -s '^{' "$1" | tail -1 | grep -o "\"$2\":[^,}]*" | cut -d: -f2 | tr -d '"'; }
count_lines() { grep -c "$2" "$1"; }
# wait_until TIMEOUT_S COMMAND...: polls COMMAND every 10 ms.
wait_until() {
  local t=$1 i
  shift
  for ((i = 0; i < t * 100; ++i)); do
    "$@" && return 0
    sleep 0.01
  done
  return 1
}
pull_out() { [ "$(field "$1" pulls_sent)" -ge 1 ] 2>/dev/null; }
state_applied() { [ "$(field "$1" states_applied)" -ge 1 ] 2>/dev/null; }
has_digest() { [ "$(field "$1" digest)" = "$2" ]; }
restarted() { [ "$(grep -c '^loaded' "$1")" -ge 2 ]; }
answered_more() { [ "$(field "$1" state_answers)" -gt "$2" ] 2>/dev/null; }
# equal LOG_A LOG_B: both synced with one peer and the same digest in their last status lines.
equal() {
  local a b
  a=$(field "$1" digest)
  b=$(field "$2" digest)
  [ -n "$a" ] && [ "$a" = "$b" ] && [ "$(field "$1" synced)" = true ] && [ "$(field "$2" synced)" = true ]
}
# phase LOG: where a kill of the joiner (whose log this is) landed.
phase() {
  local states comps
  states=$(field "$1" states_applied)
  comps=$(field "$1" store_compactions)
  if [ "${states:-0}" -eq 0 ]; then echo mid-transfer
  elif [ "${comps:-0}" -eq 0 ]; then echo mid-compaction
  else echo after; fi
}
# A random delay of 0 to $1 ms, as seconds.
delay() { printf '0.%03d' $(( RANDOM % $1 )); }

declare -A landed=([mid-transfer]=0 [mid-compaction]=0 [after]=0)
kills=0

# The world, and big's store holding it.
awk -v n="$NODES" 'BEGIN {
  pad = sprintf("%0200d", 0);
  printf "{\"quiver_world\": 1, \"nodes\": [\n";
  for (i = 0; i < n; ++i)
    printf "%s{\"name\": \"n%d\", \"type\": \"thing\", \"attrs\": {\"i\": %d, \"pad\": \"%s%d\"}}\n", (i ? "," : ""), i, i, pad, i;
  printf "], \"edges\": [], \"rt\": []}\n" }' >"$WORK/world.json"
start big "$WORK/big" batch "$WORK/big-seed.log" --world "$WORK/world.json" --status-ms 200
wait_until 60 grep -q 'seeded' "$WORK/big-seed.log" || fail "big did not seed its world"
kill -TERM "$started"
wait "$started" || fail "big did not stop cleanly after seeding"

BIG_LOG=$WORK/big.log
start_big() {
  start big "$WORK/big" batch "$BIG_LOG" --status-ms 20
  big=$started
  wait_until 60 grep -q '^{' "$BIG_LOG" || fail "big did not come up"
}
: >"$BIG_LOG"
start_big

# restart_joiner ROUND WHAT ACKED: restarts round ROUND's joiner (killed as WHAT says) from its
# store, checks that it reloaded at least ACKED and converges with big, then stops it.
restart_joiner() {
  local r=$1 what=$2 acked=${3:-0} log=$WORK/joiner-$1.log store=$WORK/joiner-$1
  start "joiner$r" "$store" always "$log" --count-hz 0.0001 --status-ms 50
  local j=$started
  wait_until 30 restarted "$log" || fail "round $r: the joiner did not restart"
  grep -q 'set aside' "$log" && echo "  round $r: the joiner's store was set aside: $(grep 'set aside' "$log" | tail -1)"
  local loaded
  loaded=$(last_loaded "$log")
  [ "$loaded" -ge "$acked" ] || fail "round $r: acknowledged $acked, reloaded $loaded ($what)"
  wait_until 60 equal "$log" "$BIG_LOG" || fail "round $r: the replicas did not converge after the restart ($what)"
  echo "  round $r: $what; acknowledged $acked, reloaded $loaded; replicas equal ($(field "$log" digest))"
  kill -TERM "$j"
  wait "$j" 2>/dev/null
}

# 1. The joiner killed during the transfer (or its compaction), restarted from its store.
joiner_round() {  # ROUND
  local r=$1 log=$WORK/joiner-$1.log store=$WORK/joiner-$1
  start "joiner$r" "$store" always "$log" --count-hz 200 --status-ms 20
  local j=$started
  wait_until 20 pull_out "$log" || fail "round $r: the joiner sent no pull"
  sleep "$(delay 3000)"
  kill -9 "$j"
  wait "$j" 2>/dev/null
  kills=$((kills + 1))
  local where acked
  where=$(phase "$log")
  landed[$where]=$((landed[$where] + 1))
  acked=$(last_acked "$log")
  restart_joiner "$r" "joiner killed $where" "$acked"
}

# 2. The sender killed during the transfer, restarted from its store.
sender_round() {  # ROUND
  local r=$1 log=$WORK/joiner-$1.log store=$WORK/joiner-$1
  local answers
  answers=$(field "$BIG_LOG" state_answers)
  start "joiner$r" "$store" always "$log" --count-hz 200 --status-ms 20
  local j=$started
  wait_until 20 answered_more "$BIG_LOG" "${answers:-0}" || fail "round $r: big answered no pull with its state"
  sleep "$(delay 300)"
  kill -9 "$big"
  wait "$big" 2>/dev/null
  kills=$((kills + 1))
  local where
  where=$(phase "$log")
  [ "$where" = mid-transfer ] || where=after
  landed[sender-$where]=$(( ${landed[sender-$where]:-0} + 1 ))
  start_big
  wait_until 60 state_applied "$log" || fail "round $r: the joiner never received the state after big's restart"
  # The joiner stops (its last status line is its final state); big must end equal to it.
  kill -TERM "$j"
  wait "$j" || fail "round $r: the joiner exited with an error"
  local d acked
  d=$(field "$log" digest)
  acked=$(last_acked "$log")
  [ "$(field "$log" synced)" = true ] || fail "round $r: the joiner was not synced when it stopped"
  wait_until 30 has_digest "$BIG_LOG" "$d" || fail "round $r: big did not reach the joiner's final digest $d"
  echo "  round $r: sender killed $where; joiner acknowledged $acked; replicas equal ($d)"
}

# 3. Both at once during a transfer.
power_cut_round() {  # ROUND
  local r=$1 log=$WORK/joiner-$1.log store=$WORK/joiner-$1
  start "joiner$r" "$store" always "$log" --count-hz 200 --status-ms 20
  local j=$started
  wait_until 20 pull_out "$log" || fail "round $r: the joiner sent no pull"
  sleep "$(delay 600)"
  kill -9 "$j" "$big"
  wait "$j" "$big" 2>/dev/null
  kills=$((kills + 2))
  local where acked
  where=$(phase "$log")
  landed[both-$where]=$(( ${landed[both-$where]:-0} + 1 ))
  acked=$(last_acked "$log")
  start_big
  restart_joiner "$r" "both killed (joiner $where)" "$acked"
}

round=0
for ((k = 0; k < ${JOINER_ROUNDS:-5}; ++k)); do joiner_round $((round++)); done
for ((k = 0; k < ${SENDER_ROUNDS:-3}; ++k)); do sender_round $((round++)); done
power_cut_round $((round++))
kill -TERM "$big"
wait "$big" 2>/dev/null
summary="joiner killed mid-transfer ${landed[mid-transfer]}, mid-compaction ${landed[mid-compaction]}, after ${landed[after]}"
summary+="; sender killed mid-transfer ${landed[sender-mid-transfer]:-0}, after ${landed[sender-after]:-0}"
summary+="; both killed at once (joiner mid-transfer ${landed[both-mid-transfer]:-0}, mid-compaction ${landed[both-mid-compaction]:-0}, after ${landed[both-after]:-0})"
echo "kill points: $summary"
mid=$(( landed[mid-transfer] + ${landed[sender-mid-transfer]:-0} + ${landed[both-mid-transfer]:-0} ))
[ "$mid" -gt 0 ] || fail "no kill landed mid-transfer (raise STATE_NODES)"
echo "state_transfer_crash_test passed: $kills processes killed with SIGKILL ($mid mid-transfer), no acknowledged write lost under always, replicas equal"
