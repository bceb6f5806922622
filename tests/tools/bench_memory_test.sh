#!/bin/sh
# quiver bench memory measures what it reports: more nodes, attributes or edges cost more heap, and
# the payload it counts is what it wrote (names and values). Not a speed or size target (those are
# the benchmark's, docs/performance.md). No network.
# Usage: bench_memory_test.sh QUIVER
set -u
q=$1
fail() { echo "FAILED: $*"; exit 1; }
field() { echo "$1" | grep -o "\"$2\":[^,}]*" | head -1 | cut -d: -f2; }
a=$("$q" bench memory --nodes 400 --runs 1) || fail "bench memory exited $?"
b=$("$q" bench memory --nodes 400 --runs 1 --attrs 0 --edges 0) || fail "bench memory (bare) exited $?"
echo "$a"
echo "$b"
python3 - "$a" "$b" <<'PY' || fail "the figures do not hold together"
import json, sys
a, b = json.loads(sys.argv[1]), json.loads(sys.argv[2])
assert a["bench"] == "memory" and a["nodes"] == 400 and a["attrs_per_node"] == 10 and a["edges_per_node"] == 3
assert a["bytes_per_attribute"] > 0 and a["bytes_per_edge"] > 0, a
# A node with 10 attributes and 3 edges holds more than a bare one, and at least its payload.
assert a["bytes_per_node"] > b["bytes_per_node"] > 0, (a, b)
assert a["bytes_per_node"] >= a["payload_bytes_per_node"] > b["payload_bytes_per_node"] > 0, (a, b)
# The parts add up to the whole within a tenth (the heap's own rounding aside).
parts = a["bytes_per_bare_node"] + 10 * a["bytes_per_attribute"] + 3 * a["bytes_per_edge"]
assert abs(parts - a["bytes_per_node"]) <= 0.1 * a["bytes_per_node"], (parts, a)
PY
echo "bench memory: ok"
