#!/bin/sh
# quiver bench all --quick: every benchmark and every installed peer runs and exits 0 (a peer
# that is not installed is listed as absent, with the reason), the summary sets Quiver's figures
# beside ddsperf's and tf2's measured in the same run, and the page shows plots that exist. Not a
# speed target (docs/performance.md has the figures). Loopback only (the embedded configuration).
# Usage: bench_all_test.sh QUIVER
set -u
q=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
"$q" bench all --quick --domain 56 --out "$out/report" >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 0 ] || { cat "$out/stderr"; fail "bench all exited $rc"; }
cat "$out/stdout"
python3 - "$out/report" <<'PY' || fail "the report"
import json, os, re, sys
d = sys.argv[1]
r = json.load(open(os.path.join(d, "bench.json")))
names = {(x["name"], x["side"]) for x in r["runs"]}
for want in [("dds", "quiver"), ("dds", "ddsperf"), ("crdt-batch-1", "quiver"), ("crdt-batch-1", "yjs"),
             ("transforms", "quiver"), ("transforms", "tf2"), ("memory", "quiver"), ("footprint", "quiver"),
             ("scale", "quiver")]:
    assert want in names, (want, names)
for x in r["runs"]:
    if "absent" in x:
        assert x["side"] != "quiver" and x["absent"], x  # only a peer may be absent, and says why
        print("absent:", x["name"], x["side"], x["absent"])
    else:
        assert x.get("exit", 0) == 0 and x["results"], x
s = {row["figure"]: row for row in r["summary"]}
lat = s["DDS latency p50 (us), one change"]
assert lat["peer_value"] > 0 and lat["quiver"] > 0 and abs(lat["ratio"] - lat["quiver"] / lat["peer_value"]) < 0.01, lat
assert s["DDS delivered updates/s, unbatched"]["peer_value"] > 0
assert s["transform lookups/s, latest"]["peer_value"] > 0
page = open(os.path.join(d, "index.html")).read()
images = re.findall(r"<img src=([\w.]+)", page)
assert len(images) >= 4, images
for i in images:
    assert os.path.getsize(os.path.join(d, i)) > 1000, i
PY
echo "bench all: ok"
