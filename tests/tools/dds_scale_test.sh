#!/bin/sh
# 32 agent processes over DDS with the gossip membership (issue 22): a writer's changes reach all
# 31 others, none goes missing, and one more agent joins late and gets everything
# (`quiver bench dds-scale`, its "completed" field), its members run as the lean quiver-agent.
# Loopback only (the embedded configuration).
# Usage: dds_scale_test.sh QUIVER
set -eu
q=$1
fail() { echo "FAILED: $*"; exit 1; }
out=$("$q" bench dds-scale --agents 32 --changes 100 --rate 20 --idle 1 --membership gossip --domain 93) ||
  fail "quiver bench dds-scale exited $?: $out"
echo "$out"
echo "$out" | grep -q '"agents":32' || fail "no line for 32 agents"
echo "$out" | grep -q '"all_joined":true' || fail "the writer did not see all 31 others"
echo "$out" | grep -q '"deliveries":3100' || fail "not every change reached every other agent"
echo "$out" | grep -q '"missing":0' || fail "changes went missing"
echo "$out" | grep -Eq '"join_ms":[0-9]' || fail "the late joiner did not sync"
echo "$out" | grep -q '"completed":true' || fail "the run did not complete"
# The members are the lean quiver-agent's role processes (its bench-dds-role), not the whole CLI.
echo "$out" | grep -q '"member_executable":"quiver-agent"' || fail "the members did not run as quiver-agent"
echo "dds_scale_test passed: 32 processes, 3,100 deliveries, a late joiner synced"
