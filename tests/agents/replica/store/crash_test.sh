#!/usr/bin/env bash
# Crash tests of the durable store with real agent processes over Cyclone DDS on loopback
# (docs/persistence.md). Usage: crash_test.sh QUIVER [SEED]
#
#  1. `always`: agent "robot" raises a counter at 300 Hz and prints "acked N" after each commit
#     returned; it compacts its store every 10 KiB of log. It is killed with SIGKILL at random
#     moments (mid-write, mid-compaction: they happen several times a second) and restarted from
#     its store: the count it reloads must be at least the last one it acknowledged, and it must
#     keep its incarnation.
#  2. A power cut: both agents are killed at once and restarted from their stores; the count
#     survives and the two replicas end with equal digests.
#  3. `batch`: the same kills; the replica may lose its last unflushed changes locally, but it
#     takes a new incarnation and its peer gives them back: the replicas end equal.
set -uo pipefail
QUIVER=$1
SEED=${2:-$(( $(date +%s) % 100000 ))}
echo "crash_test seed $SEED (replay: $0 $QUIVER $SEED)"
RANDOM=$SEED
WORK=$(mktemp -d)
DOMAIN=$(( 100 + SEED % 100 ))
. "$(dirname "$0")/crash_lib.sh"

wait_for_line() {  # FILE PATTERN COUNT TIMEOUT_S
  local i
  for ((i = 0; i < $4 * 20; ++i)); do
    [ "$(grep -c "$2" "$1")" -ge "$3" ] && return 0
    sleep 0.05
  done
  return 1
}
# final_digest LOG: the digest of the last status line.
final_digest() { grep -o '"digest":"[0-9a-f]*"' "$1" | tail -1; }

kills=0
run_kills() {  # DURABILITY ROUNDS
  local durability=$1 rounds=$2 robot_log=$WORK/robot-$1.log peer_log=$WORK/peer-$1.log
  start peer "$WORK/peer-$durability" batch "$peer_log" --status-ms 200
  local peer=$started
  local starts=1
  start robot "$WORK/robot-$durability" "$durability" "$robot_log" --count-hz 300 --churn-hz 50 --status-ms 100
  local robot=$started
  for ((r = 0; r < rounds; ++r)); do
    wait_for_line "$robot_log" '^loaded' "$starts" 10 || fail "robot did not start (round $r)"
    sleep "0.$(( 2 + RANDOM % 8 ))$(( RANDOM % 10 ))"
    kill -9 "$robot"
    wait "$robot" 2>/dev/null
    kills=$((kills + 1))
    local acked
    acked=$(last_acked "$robot_log")
    [ -n "$acked" ] || fail "robot acknowledged nothing (round $r)"
    start robot "$WORK/robot-$durability" "$durability" "$robot_log" --count-hz 300 --churn-hz 50 --status-ms 100
    robot=$started
    starts=$((starts + 1))
    wait_for_line "$robot_log" '^loaded' "$starts" 10 || fail "robot did not restart (round $r)"
    local loaded
    loaded=$(last_loaded "$robot_log")
    if [ "$durability" = always ]; then
      [ "$loaded" -ge "$acked" ] || fail "always: acknowledged $acked, reloaded $loaded (round $r)"
      # Every restart so far logged its store line (before "loaded"); the first start made the store.
      # Counted over the whole log: at 300 acks a second, a tail of it may already be past the line.
      local kept
      kept=$(grep -c "kept its incarnation" "$robot_log")
      [ "$kept" -eq $((starts - 1)) ] ||
        fail "always: the incarnation was not kept (round $r: $kept of $((starts - 1)) restarts kept it)"
    fi
    echo "  $durability round $r: acknowledged $acked, reloaded $loaded"
  done
  # Compactions the robot's runs reported (each run counts its own).
  local compactions
  compactions=$(grep -o '"store_compactions":[0-9]*' "$robot_log" | cut -d: -f2 | awk '$1 > 0' | wc -l)
  [ "$compactions" -gt 0 ] || fail "$durability: the robot never compacted its store"
  # A power cut: both at once.
  kill -9 "$robot" "$peer"
  wait "$robot" "$peer" 2>/dev/null
  kills=$((kills + 2))
  local acked
  acked=$(last_acked "$robot_log")
  : >"$WORK/end-robot.log"
  : >"$WORK/end-peer.log"
  start peer "$WORK/peer-$durability" batch "$WORK/end-peer.log" --status-ms 200 --run-for 4
  local p2=$started
  start robot "$WORK/robot-$durability" "$durability" "$WORK/end-robot.log" --count-hz 0.0001 --status-ms 200 --run-for 4
  local r2=$started
  wait "$p2" || fail "peer exited with an error after the power cut"
  wait "$r2" || fail "robot exited with an error after the power cut"
  local loaded
  loaded=$(last_loaded "$WORK/end-robot.log")
  if [ "$durability" = always ]; then
    [ "$loaded" -ge "$acked" ] || fail "power cut under always: acknowledged $acked, reloaded $loaded"
  fi
  local d1 d2
  d1=$(final_digest "$WORK/end-robot.log")
  d2=$(final_digest "$WORK/end-peer.log")
  [ -n "$d1" ] && [ "$d1" = "$d2" ] || fail "$durability: replicas differ after the power cut: $d1 vs $d2"
  grep -q '"store_ok":true' "$WORK/end-robot.log" || fail "robot's store reports an error"
  echo "  $durability power cut: acknowledged $acked, reloaded $loaded, replicas equal ($d1)"
}

run_kills always 6
run_kills batch 4
echo "crash_test passed: $kills processes killed with SIGKILL, no acknowledged write lost under always, replicas equal"
