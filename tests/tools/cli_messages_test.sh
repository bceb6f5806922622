#!/bin/sh
# The quiver command's own messages: --version, an unknown command named as such, log levels, and
# the progress line of a long run, drawn on a terminal (script(1) provides one) and never on a pipe.
set -eu
q=$1
fail() { echo "FAILED: $*" >&2; exit 1; }

$q --version | grep -Eqx "quiver [0-9]+\.[0-9]+\.[0-9]+" || fail "--version prints 'quiver X.Y.Z'"

if out=$($q frobnicate 2>&1); then fail "an unknown command exits non-zero"; fi
echo "$out" | grep -q "quiver: unknown command 'frobnicate' (the commands are: sim, bench" || fail "unknown command: $out"
if out=$($q bench frobnicate 2>&1); then fail "an unknown bench exits non-zero"; fi
echo "$out" | grep -q "quiver bench: unknown command 'frobnicate'" || fail "unknown bench: $out"
if out=$($q 2>&1); then fail "no command exits non-zero"; fi
echo "$out" | grep -q "quiver: which command?" || fail "no command: $out"

# Commands with option groups but no subcommands still run (the DDS one only on loopback: ctest
# runs in a namespace of its own).
out=$($q dump --domain 198 --timeout 0.3 2>&1) || true
echo "$out" | grep -q "\[quiver dump\] error: no agent answered on DDS domain 198" || fail "quiver dump runs: $out"

$q sim --steps 5 2>&1 >/dev/null | grep -q "\[quiver sim\] info: seed 1, 5 agents, 5 steps" || fail "info is logged by default"
if $q --log-level warn sim --steps 5 2>&1 >/dev/null | grep -q "info"; then fail "--log-level warn hides info"; fi
if QUIVER_LOG_LEVEL=error $q sim --steps 5 2>&1 >/dev/null | grep -q "info"; then fail "QUIVER_LOG_LEVEL=error hides info"; fi
if $q --log-level loud sim --steps 5 2>/dev/null; then fail "an unknown level is refused"; fi

tty=$(script -qec "$q sim --steps 2000" /dev/null | tr '\r' '\n')
echo "$tty" | grep -q "^2000/2000 steps (100%)" || fail "no progress line on a terminal: $tty"
echo "$tty" | grep -q '"steps":2000' || fail "the result follows the progress line: $tty"
if $q sim --steps 2000 2>&1 >/dev/null | grep -q "/2000 steps"; then fail "a progress line while stdout is a pipe"; fi
# An agent process prints one status line after a clean stop, unless --no-final-status.
out=$($q agent --name final-status-test --domain 197 --run-for 0.2 --join-wait 0 --hand-over 0 2>/dev/null)
echo "$out" | grep -q '^{.*"name":"final-status-test"' || fail "no final status line by default: $out"
out=$($q agent --name final-status-test --domain 197 --run-for 0.2 --join-wait 0 --hand-over 0 --no-final-status 2>/dev/null)
[ -z "$out" ] || fail "--no-final-status still printed: $out"
echo "cli messages: ok"
