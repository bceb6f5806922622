#!/bin/sh
# quiver echo joins a live domain (loopback) as an observer and prints the graph's changes as they
# arrive: who made each, what it is, and its values; --type keeps one type's, --node one node's; what the domain held
# before echo joined is not printed as news. Usage: echo_test.sh QUIVER WORLD
set -u
q=$1
world=$2
domain=195
work=$(mktemp -d)
pids=""
trap 'for p in $pids; do kill "$p" 2>/dev/null; done; rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; for f in "$work"/*; do echo "--- $f"; tail -5 "$f"; done; exit 1; }
# A writer that seeds the world, then changes the graph at random for 8 s, and counts up in its
# node echo-writer.counter ten times a second (which the random changes leave alone).
"$q" agent --name echo-writer --domain $domain --world "$world" --churn-hz 20 --churn-for 8 --count-hz 10 --run-for 10 --hand-over 0 \
  --status-ms 100 >"$work/writer.out" 2>"$work/writer.err" &
pids="$pids $!"
# The writer is up (its world seeded) before echo joins: the world is not news to echo.
i=0
while ! grep -q '^{' "$work/writer.out" 2>/dev/null; do
  i=$((i + 1)); [ $i -lt 100 ] || fail "the writer did not start"; sleep 0.1
done
"$q" echo --domain $domain --json --count 12 --timeout 30 >"$work/all.jsonl" 2>"$work/all.err" &
e1=$!
"$q" echo --domain $domain --json --type person --count 3 --timeout 30 >"$work/person.jsonl" 2>"$work/person.err" &
e2=$!
"$q" echo --domain $domain --json --node echo-writer.counter --count 2 --timeout 30 >"$work/counter.jsonl" 2>"$work/counter.err" &
e3=$!
pids="$pids $e1 $e2 $e3"
wait $e1 || fail "quiver echo exited $?"
wait $e2 || fail "quiver echo --type exited $?"
wait $e3 || fail "quiver echo --node exited $?"
[ "$(grep -c '^{' "$work/all.jsonl")" = 12 ] || fail "expected 12 changes: $(cat "$work/all.jsonl")"
[ "$(grep -c '"origin":"echo-writer"' "$work/all.jsonl")" = 12 ] || fail "every change names its agent"
grep -q '"kind":"created"\|"kind":"updated"\|"kind":"deleted"' "$work/all.jsonl" || fail "no kind"
grep -q '"t_s":' "$work/all.jsonl" || fail "no time"
# The world (world, kitchen, robot, ...) was there before: its creation is not news.
if grep '"node":"kitchen"' "$work/all.jsonl" | grep -q '"kind":"created"'; then
  fail "the world seeded before echo joined was printed as news"
fi
grep -q 'following DDS domain 195' "$work/all.err" || fail "no 'following' line: $(cat "$work/all.err")"
[ "$(grep -c '^{' "$work/person.jsonl")" = 3 ] || fail "expected 3 person changes: $(cat "$work/person.jsonl")"
if grep -v '"type":"person"' "$work/person.jsonl" | grep -q .; then fail "--type person let another type through"; fi
# --node keeps the changes of one node (and of its edges) by name.
[ "$(grep -c '^{' "$work/counter.jsonl")" = 2 ] || fail "expected 2 changes of the counter: $(cat "$work/counter.jsonl")"
if grep -v 'echo-writer.counter' "$work/counter.jsonl" | grep -q .; then fail "--node let another node through"; fi
# The text form, one line per change.
"$q" echo --domain $domain --count 2 --timeout 30 >"$work/text.out" 2>/dev/null || fail "text echo exited $?"
[ "$(grep -c ' echo-writer  ' "$work/text.out")" = 2 ] || fail "text lines: $(cat "$work/text.out")"
echo PASS
