#!/bin/sh
# quiver bench scale runs the simulator for each number of agents and prints one JSON line each,
# with the figures scripts/plot_scale.py draws; the plot script writes a PNG and an SVG of them.
# Usage: bench_scale_test.sh QUIVER SOURCE_DIR
set -eu
q=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
"$q" bench scale --agents 2,4 --steps 100 --seed 3 > "$work/scale.jsonl" || fail "quiver bench scale exited $?"
cat "$work/scale.jsonl"
[ "$(grep -c '"bench":"scale"' "$work/scale.jsonl")" -eq 2 ] || fail "expected 2 JSON lines"
for n in 2 4; do
  line=$(grep "\"agents\":$n," "$work/scale.jsonl") || fail "no line for $n agents"
  echo "$line" | grep -q '"converged":true' || fail "$n agents did not converge"
  echo "$line" | grep -q '"invariant_violations":0' || fail "$n agents: invariant violations"
  echo "$line" | grep -Eq '"bytes_per_op_per_agent":[1-9]' || fail "$n agents: no bytes per op per agent"
  echo "$line" | grep -Eq '"idle_bytes_per_s_per_agent":[1-9]' || fail "$n agents: no idle traffic measured"
  echo "$line" | grep -q '"protocol":"gossip"' || fail "$n agents: not the gossip protocol by default"
  echo "$line" | grep -q '"heal_converged":true' || fail "$n agents: did not converge after the heal"
  echo "$line" | grep -Eq '"heal_ms":[1-9]' || fail "$n agents: no time to converge after the heal"
  echo "$line" | grep -Eq '"protocol_bytes_max":[1-9]' || fail "$n agents: no protocol state measured"
done
"$q" bench scale --agents 4 --steps 100 --seed 3 --protocol all-to-all --no-heal > "$work/before.jsonl" ||
  fail "quiver bench scale --protocol all-to-all exited $?"
grep -q '"protocol":"all-to-all"' "$work/before.jsonl" || fail "--protocol all-to-all was not used"
grep -q '"heal_ms"' "$work/before.jsonl" && fail "--no-heal still ran the heal"
"$q" bench scale --agents 0 > /dev/null 2>&1 && fail "--agents 0 was accepted"
/usr/bin/python3 "$src/scripts/plot_scale.py" "run=$work/scale.jsonl" "before=$work/before.jsonl" -o "$work/scale" ||
  fail "plot_scale.py exited $?"
for ext in png svg; do
  [ -s "$work/scale.$ext" ] || fail "no scale.$ext"
done
head -c 8 "$work/scale.png" | od -An -c | grep -q 'P   N   G' || fail "scale.png is not a PNG"
grep -q '<svg' "$work/scale.svg" || fail "scale.svg is not an SVG"
# quiver bench schedules: seeded fault schedules at a fixed number of agents, each counted.
"$q" bench schedules --agents 8 --count 4 --steps 60 --seed 41 > "$work/sched.jsonl" ||
  fail "quiver bench schedules exited $?"
cat "$work/sched.jsonl"
grep -q '"schedules":4' "$work/sched.jsonl" || fail "schedules: not 4 run"
grep -q '"converged":4' "$work/sched.jsonl" || fail "schedules: not all 4 converged"
grep -q '"failed":0' "$work/sched.jsonl" || fail "schedules: one failed"
grep -Eq '"packets_dropped":[1-9]' "$work/sched.jsonl" || fail "schedules: no fault injected"
echo "bench_scale_test passed: 2 runs, both converged, plotted as PNG and SVG; 4 fault schedules converged"
