#!/bin/sh
# quiver bench dds --stages measures what it reports: every latency sample's stages marked in the
# writer and the reader (base/stage_marks.h) pair up, each stage takes time (the DDS write and the
# delivery most), and the stages' total is the latency the benchmark reports. Not a speed target
# (docs/performance.md has the figures). Loopback only (the embedded configuration).
# Usage: bench_stages_test.sh QUIVER
set -u
q=$1
fail() { echo "FAILED: $*"; exit 1; }
out=$("$q" bench dds --domain 58 --batch 1 --readers 1 --updates 2000 --latency-samples 400 --join-nodes 1000 --stages) \
  || fail "bench dds --stages exited $?"
echo "$out"
python3 - "$out" <<'PY' || fail "the stages do not hold together"
import json, sys
r = json.loads(sys.argv[1].strip().splitlines()[-1])
s = r["stages_us_p50"]
spans = ["commit_and_encode", "sign", "dds_write", "delivery_and_wakeup", "take", "decode", "admission",
         "bookkeeping", "merge_and_events"]
assert set(spans) <= set(s), s
# (Samples whose marks were overtaken by another change's are left out: a few at most.)
assert s["samples"] >= 0.9 * r["latency_samples"] and s["samples"] + s["skipped"] >= r["latency_samples"], s
assert all(s[k] >= 0 for k in spans), s
for k in ("commit_and_encode", "dds_write", "decode", "merge_and_events"):
    assert s[k] > 0, (k, s)
# A reader that woke inside the writer's dds_write() call gives its delivery no time of its own.
assert s["woken_inside_write"] <= s["samples"], s
assert s["delivery_and_wakeup"] > 0 or 2 * s["woken_inside_write"] >= s["samples"], s
# The total is the latency the reader measured (same marks, the median of the same samples).
assert abs(s["total"] - r["latency_us_p50"]) <= 0.1 * r["latency_us_p50"] + 1, (s["total"], r["latency_us_p50"])
# The medians of the parts do not add up exactly, but they add up to about the whole.
assert 0.5 * s["total"] <= sum(s[k] for k in spans) <= 1.5 * s["total"], s
PY
echo "bench dds --stages: ok"
