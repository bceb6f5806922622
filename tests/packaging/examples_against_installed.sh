#!/usr/bin/env bash
# Installs a build of Quiver into a fresh prefix and builds examples/ against it, as a user would:
#   examples_against_installed.sh SOURCE_DIR BUILD_DIR WORK_DIR
# Checks: the graph component needs no third-party package (a consumer configures with every
# other dependency disabled); the whole examples project configures and builds (timed); the
# graph and kinematics examples run from the source root, the DDS ones on loopback; pkg-config
# files compile and link the graph example.
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
work=$3
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)
prefix=$work/prefix
generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi

step() { echo "== $*"; }

step "cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log"
test -x "$prefix/bin/quiver"
for lib in crdt graph interop kinematics replication grammar locks runtime security store agents_dds runtime_process images; do
  find "$prefix" -name "libquiver_$lib.a" | grep -q . || { echo "FAIL: no libquiver_$lib.a" >&2; exit 1; }
  find "$prefix" -name "libquiver_$lib.so" | grep -q . || { echo "FAIL: no libquiver_$lib.so" >&2; exit 1; }
done
# The examples and their sample data come with the package (the docs cite them).
for f in CMakeLists.txt worlds/kitchen.json grammars/speech.aggl graph_basics/graph_basics.cc; do
  test -f "$prefix/share/quiver/examples/$f" || { echo "FAIL: the package lacks share/quiver/examples/$f" >&2; exit 1; }
done
config_dir=$(dirname "$(find "$prefix" -name quiverConfig.cmake | head -1)")
if grep -E "CycloneDDS|fcl|urdfdom|Eigen3|nlohmann" "$config_dir/quiver-graph-targets.cmake"; then
  echo "FAIL: the graph component's targets name a third-party package" >&2
  exit 1
fi

step "a graph-only consumer, every other dependency disabled"
mkdir -p "$work/graph-only"
cat >"$work/graph-only/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(graph_only LANGUAGES CXX)
find_package(quiver 0.2 CONFIG REQUIRED COMPONENTS graph)
if(TARGET quiver::kinematics OR TARGET quiver::agents_dds)
  message(FATAL_ERROR "asked for graph only, got more")
endif()
add_executable(graph_basics ${EXAMPLE})
target_link_libraries(graph_basics PRIVATE quiver::graph)
add_executable(graph_basics_shared ${EXAMPLE})
target_link_libraries(graph_basics_shared PRIVATE quiver::graph_shared)
CMAKE
disabled=()
for p in CycloneDDS fcl urdfdom Eigen3 nlohmann_json spdlog CLI11 OpenCV; do
  disabled+=(-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON)
done
cmake --no-warn-unused-cli -S "$work/graph-only" -B "$work/graph-only/build" "${generator[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
  -DEXAMPLE="$src/examples/graph_basics/graph_basics.cc" "${disabled[@]}" >"$work/graph-only.log"
cmake --build "$work/graph-only/build" >>"$work/graph-only.log"
"$work/graph-only/build/graph_basics"
"$work/graph-only/build/graph_basics_shared"

step "find_package(quiver 0.3) refuses 0.2 (0.x: same minor version only)"
mkdir -p "$work/version"
printf 'cmake_minimum_required(VERSION 3.22)\nproject(v NONE)\nfind_package(quiver 0.3 CONFIG REQUIRED COMPONENTS graph)\n' \
  >"$work/version/CMakeLists.txt"
if cmake -S "$work/version" -B "$work/version/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/version.log" 2>&1; then
  echo "FAIL: find_package(quiver 0.3) accepted $(grep -o 'PACKAGE_VERSION "[^"]*"' "$config_dir/quiverConfigVersion.cmake")" >&2
  exit 1
fi

step "pkg-config: quiver-graph"
export PKG_CONFIG_PATH=$(dirname "$(find "$prefix" -name quiver-graph.pc | head -1)")
c++ -std=c++20 -O1 "$src/examples/graph_basics/graph_basics.cc" -o "$work/graph_basics_pc" \
  $(pkg-config --cflags --libs quiver-graph)
LD_LIBRARY_PATH=$(pkg-config --variable=libdir quiver-graph) "$work/graph_basics_pc"
pkg-config --exists --print-errors "quiver-kinematics >= 0.2" "quiver-dds >= 0.2" "quiver-interop >= 0.2"

step "an images consumer: component sim re-finds OpenCV (cv::Mat is in quiver::images' API)"
mkdir -p "$work/images"
cat >"$work/images/images.cc" <<'CPP'
#include <cstdio>

#include "quiver/agents/view/images/image_attrs.h"
using namespace quiver;

int main() {
  graph::Graph g(graph::ReplicaId{1, 1});
  auto tx = g.begin();
  auto cam = tx.create_node("camera", "camera");
  cv::Mat m(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  if (!cam.ok() || !agents::images::set_image(tx, *cam, m).ok() || !tx.commit().ok()) return 1;
  auto back = agents::images::get_image(g, *cam);
  if (!back.ok() || back->size() != m.size()) return 1;
  std::printf("images: %dx%d %s\n", back->cols, back->rows,
              agents::images::mime_type(agents::images::image_info(g, *cam)->encoding));
  return 0;
}
CPP
cat >"$work/images/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(images_consumer LANGUAGES CXX)
find_package(quiver 0.2 CONFIG REQUIRED COMPONENTS sim)
add_executable(images images.cc)
target_link_libraries(images PRIVATE quiver::images)
add_executable(images_shared images.cc)
target_link_libraries(images_shared PRIVATE quiver::images_shared)
CMAKE
cmake -S "$work/images" -B "$work/images/build" "${generator[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$work/images.log"
cmake --build "$work/images/build" >>"$work/images.log"
"$work/images/build/images"
# The installed shared libraries carry no RUNPATH: their own dependencies (libquiver_crdt.so
# under libquiver_graph.so) are found through the loader's path.
libdir=$(dirname "$(find "$prefix" -name libquiver_images.so | head -1)")
LD_LIBRARY_PATH=$libdir "$work/images/build/images_shared"
c++ -std=c++20 -O1 "$work/images/images.cc" -o "$work/images_pc" $(pkg-config --cflags --libs quiver-sim)
LD_LIBRARY_PATH=$(pkg-config --variable=libdir quiver-graph) "$work/images_pc"

step "examples/ against the installed package"
start=$(date +%s%N)
cmake -S "$src/examples" -B "$work/examples" "${generator[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$work/examples.log"
cmake --build "$work/examples" >>"$work/examples.log"
end=$(date +%s%N)
echo "examples configured and built in $(( (end - start) / 1000000 )) ms"

cd "$src"  # the examples read examples/worlds, examples/grammars and examples/urdf from here
step "graph_basics";      "$work/examples/graph_basics"
step "kinematics_lookup"; "$work/examples/kinematics_lookup"
step "grammar_agent";     timeout 60 "$work/examples/grammar_agent"
step "dds_agent";         timeout 60 "$work/examples/dds_agent" speech 1
# The tutorial of docs/agents.md, as it tells a newcomer to run it: the greeter beside an agent
# named speech, both seeding the kitchen world; the person ends greeted, and the greeter hears speech.
step "tutorial: greeter beside quiver agent --name speech"
"$prefix/bin/quiver" agent --name speech --world examples/worlds/kitchen.json --domain 192 --run-for 15 \
  >"$work/speech.out" 2>"$work/speech.err" &
speech=$!
timeout 60 "$work/examples/greeter" --world examples/worlds/kitchen.json --domain 192 --text "Good morning" \
  --status-ms 500 --run-for 6 >"$work/greeter.out" 2>"$work/greeter.err"
grep '^{' "$work/greeter.out" | tail -1 | grep -q '"actions_finished":1' ||
  { echo "FAIL: the greeter did not greet once: $(tail -1 "$work/greeter.out")" >&2; kill "$speech"; exit 1; }
grep -q "speech is here" "$work/greeter.err" || { echo "FAIL: the greeter did not hear speech" >&2; kill "$speech"; exit 1; }
"$prefix/bin/quiver" dump --domain 192 --json --timeout 10 | grep -q '"greeting": *"Good morning"' ||
  { echo "FAIL: the person was not greeted in the shared graph" >&2; kill "$speech"; exit 1; }
kill "$speech"
wait "$speech" 2>/dev/null || true
# Your own agents and checks in the simulator: three seeded runs of a scenario file with a
# partition, loss and kill -9; it exits non-zero when a check fails.
step "sim_scenario";      timeout 120 "$work/examples/sim_scenario" examples/sim_scenario/pingpong.json 1 3
echo "PASS"
