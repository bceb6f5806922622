#!/usr/bin/env bash
# The lean executables (tools/CMakeLists.txt): `quiver agent` becomes quiver-agent, which maps
# no OpenCV, Graphviz, Python or VTK; quiver-barthel links OpenCV's three modules and none of the
# rest, and runs the Barthel roles only; the demo's configuration (scripts/build-options.sh, with
# OpenCV's CMake package hidden as on a machine with only the demo's packages) plans quiver-barthel
# alone. Loopback only (the embedded configuration). Not a memory target: `quiver bench
# footprint` measures that (docs/performance.md).
# Usage: lean_executables_test.sh QUIVER SOURCE_DIR
set -u
q=$1 src=$2
dir=$(dirname "$q")
work=$(mktemp -d)
pid=""
trap '[ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
heavy='libopencv|libgvc|libcgraph|libpython|libvtk|libfcl|liburdfdom'

# An agent started as `quiver agent` (its status line once it runs), measured while it runs.
# Writes the name of the executable it became and the heavy libraries it maps to $work/maps.
agent_maps() {
  "$q" agent --name lean-test --world "$src/examples/worlds/kitchen.json" --domain 59 --status-ms 200 --run-for 30 \
    >"$work/agent.out" 2>"$work/agent.err" &
  pid=$!
  for _ in $(seq 1 100); do grep -q '"nodes":10' "$work/agent.out" 2>/dev/null && break; sleep 0.1; done
  grep -q '"nodes":10' "$work/agent.out" || { cat "$work/agent.err"; fail "the agent did not seed kitchen.json"; }
  { basename "$(readlink /proc/$pid/exe)"
    grep -oE "/($heavy)[^/ ]*\.so[^/ ]*" /proc/$pid/maps | sort -u | tr '\n' ' '
    echo
    tr '\0' '\n' </proc/$pid/environ | grep '^GLIBC_TUNABLES=' || echo "GLIBC_TUNABLES unset"; } >"$work/maps"
  kill -TERM "$pid"
  wait "$pid" || fail "the agent exited $? after SIGTERM"
  pid=""
}

agent_maps
out=$(cat "$work/maps")
echo "quiver agent: $out"
[ "$(echo "$out" | sed -n 1p)" = quiver-agent ] || fail "quiver agent did not become quiver-agent: $out"
[ -z "$(echo "$out" | sed -n 2p | tr -d ' ')" ] || fail "quiver-agent maps $(echo "$out" | sed -n 2p)"
# Its heap may use transparent huge pages (tools/huge_pages.h): it runs with glibc's tunable set,
# and without it when QUIVER_HUGE_PAGES=0.
echo "$out" | sed -n 3p | grep -q 'glibc.malloc.hugetlb=1' || fail "quiver-agent runs without glibc.malloc.hugetlb=1: $out"
QUIVER_HUGE_PAGES=0 agent_maps
out=$(cat "$work/maps")
echo "$out" | sed -n 3p | grep -q 'hugetlb' && fail "QUIVER_HUGE_PAGES=0 still set the tunable: $out"
# The check can fail: the same command kept inside quiver maps OpenCV.
QUIVER_IN_ONE_EXECUTABLE=1 agent_maps
out=$(cat "$work/maps")
[ "$(echo "$out" | sed -n 1p)" = quiver ] || fail "QUIVER_IN_ONE_EXECUTABLE=1 left quiver: $out"
echo "$out" | sed -n 2p | grep -q libopencv || fail "quiver itself maps no OpenCV?: $out"

# What each lean executable links.
ldd "$dir/quiver-agent" | grep -E "$heavy" && fail "quiver-agent links the above"
ldd "$dir/quiver-barthel" | grep -E 'libgvc|libcgraph|libpython|libvtk|libfcl|liburdfdom' && fail "quiver-barthel links the above"
for m in core imgproc imgcodecs; do
  ldd "$dir/quiver-barthel" | grep -q "libopencv_$m" || fail "quiver-barthel does not link OpenCV's $m"
done
"$dir/quiver-barthel" run navigation >"$work/out" 2>&1 && fail "quiver-barthel ran the AGM role navigation"
grep -q "navigation" "$work/out" || { cat "$work/out"; fail "no error naming the role"; }
"$q" run navigation --help >/dev/null || fail "quiver run navigation --help (the AGM roles stay in quiver)"
"$dir/quiver-barthel" --help | grep -q scenario || fail "quiver-barthel --help lists no scenario"

# The demo's configuration, with OpenCV's CMake package hidden: it finds the three modules
# itself, and builds quiver-barthel only.
if command -v cmake >/dev/null && command -v ninja >/dev/null; then
  source "$src/scripts/build-options.sh"
  cmake -S "$src" -B "$work/demo" -G Ninja -DCMAKE_BUILD_TYPE=Release "${demo_only[@]}" \
    -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON >"$work/cmake.log" 2>&1 || { cat "$work/cmake.log"; fail "the demo's configuration"; }
  grep -q "OpenCV: no CMake package" "$work/cmake.log" || fail "the demo's configuration did not find OpenCV's modules itself"
  targets=$(ninja -C "$work/demo" -t targets all)
  echo "$targets" | grep -q '^quiver-barthel:' || fail "the demo's configuration has no quiver-barthel"
  echo "$targets" | grep -qE '^quiver:' && fail "the demo's configuration builds quiver"
  link=$(ninja -C "$work/demo" -t commands quiver-barthel | tail -1)
  echo "$link" | grep -q libopencv_imgcodecs || fail "quiver-barthel's link line lacks OpenCV: $link"
  echo "$link" | grep -qE 'gvc|cgraph|python|httplib|fcl|urdfdom' && fail "quiver-barthel's link line: $link"
  echo "demo configuration: $(ninja -C "$work/demo" -t commands quiver-barthel | grep -c ' -c ') compile steps"
fi
echo "lean executables: ok"
