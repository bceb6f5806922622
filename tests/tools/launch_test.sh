#!/bin/sh
# quiver launch starts the agents of a launch file, each logging to its own file, restarts the one
# that fails as its policy says, and stops them all cleanly together (at --for, or on SIGINT),
# printing one JSON summary; a malformed file is refused naming the field. Loopback DDS only.
# Usage: launch_test.sh QUIVER SOURCE_DIR
set -u
q=$1
src=$2
work=$(mktemp -d)
trap 'pkill -f "launch-test-" 2>/dev/null; rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; cat "$work"/err* 2>/dev/null | tail -20; exit 1; }
field() { grep '^{' "$1" | tail -1 | grep -o "\"$2\":[^,}]*" | head -1 | cut -d: -f2 | tr -d '"'; }
cat >"$work/team.json" <<JSON
{"logs": "logs", "stop_grace_s": 5, "agents": [
  {"name": "w", "args": ["agent", "--name", "launch-test-w", "--domain", "194", "--world",
                         "$src/examples/worlds/kitchen.json", "--churn-hz", "10", "--churn-for", "2",
                         "--status-ms", "200"]},
  {"name": "f", "args": ["agent", "--name", "launch-test-f", "--domain", "194", "--status-ms", "200"],
   "start_after_s": 0.5},
  {"name": "flaky", "args": ["agent", "--name", "launch-test-x", "--domain", "194", "--world", "/nonexistent/world.json"],
   "restart": "on-failure", "max_restarts": 2, "restart_delay_s": 0.2}
]}
JSON
"$q" launch "$work/team.json" --for 4 >"$work/out.json" 2>"$work/err1"
rc=$?
[ "$rc" = 1 ] || fail "a run with an agent that kept failing exited $rc, not 1"
summary=$(cat "$work/out.json")
echo "$summary" | grep -q '"flaky":{"last_status":2,"starts":3}' || fail "flaky: not started 3 times (2 restarts): $summary"
echo "$summary" | grep -q '"w":{"last_status":0,"starts":1}' || fail "w did not stop cleanly: $summary"
echo "$summary" | grep -q '"f":{"last_status":0,"starts":1}' || fail "f did not stop cleanly: $summary"
for a in w f flaky; do [ -s "$work/logs/$a.log" ] || fail "no log for $a"; done
grep -q "cannot read\|No such file\|nonexistent" "$work/logs/flaky.log" || fail "flaky's log does not say why"
[ "$(field "$work/logs/w.log" digest)" = "$(field "$work/logs/f.log" digest)" ] || fail "w and f ended apart"
[ "$(field "$work/logs/f.log" nodes)" -gt 5 ] || fail "f holds no world"
pgrep -f "launch-test-" >/dev/null && fail "agents left running after the launcher ended"
grep -q "restarting" "$work/err1" || fail "the launcher did not say it restarts flaky"
# SIGINT stops them all cleanly: exit 0.
cat >"$work/two.json" <<JSON
{"agents": [
  {"name": "a", "args": ["agent", "--name", "launch-test-a", "--domain", "194", "--status-ms", "200"]},
  {"name": "b", "args": ["agent", "--name", "launch-test-b", "--domain", "194", "--status-ms", "200"]}
]}
JSON
"$q" launch "$work/two.json" --logs "$work/logs2" >"$work/out2.json" 2>"$work/err2" &
l=$!
sleep 2
kill -INT $l
wait $l
rc=$?
[ "$rc" = 0 ] || fail "stopped by SIGINT: exit $rc: $(cat "$work/out2.json")"
grep -q '"ok":true' "$work/out2.json" || fail "not ok: $(cat "$work/out2.json")"
pgrep -f "launch-test-" >/dev/null && fail "agents left running after SIGINT"
# A malformed file names what is wrong.
echo '{"agents": [{"name": "a b", "args": ["agent"]}]}' >"$work/bad.json"
"$q" launch "$work/bad.json" 2>"$work/err3" && fail "a bad name was accepted"
grep -q "agents\[0\].name must be 1 to 64 letters" "$work/err3" || fail "bad name: $(cat "$work/err3")"
echo '{"agents": [{"name": "a", "args": ["agent"], "restart": "sometimes"}]}' >"$work/bad.json"
"$q" launch "$work/bad.json" 2>"$work/err3" && fail "a bad restart was accepted"
grep -q "agents\[0\].restart must be never, on-failure or always" "$work/err3" || fail "bad restart: $(cat "$work/err3")"
# Every launch file the package ships reads as the launcher reads it (--check starts nothing).
for f in "$src"/examples/launch/*.json; do
  "$q" launch "$f" --check >"$work/check.txt" 2>"$work/err4" || fail "$f: $(cat "$work/err4")"
  n=$(grep -c '"name"' "$f")
  [ "$(grep -c ': quiver ' "$work/check.txt")" = "$n" ] || fail "$f: --check listed $(cat "$work/check.txt")"
done
grep -q '^agm-planner: quiver run agm-planner --mission clean-table' "$work/check.txt" ||
  [ "$(basename "$f")" != agm.json ] || fail "agm.json: $(cat "$work/check.txt")"
"$q" launch "$work/bad.json" --check 2>"$work/err5" && fail "--check accepted a bad file"
grep -q "agents\[0\].restart must be" "$work/err5" || fail "--check: $(cat "$work/err5")"
echo PASS
