#!/usr/bin/env bash
# add_subdirectory(quiver) from a parent project, graph only:
#   add_subdirectory_parent.sh SOURCE_DIR WORK_DIR
# The parent configures twice: with no build type (it must stay empty) and with Debug (it must
# stay Debug), with Cyclone DDS, FCL, urdfdom, Eigen, OpenCV, spdlog and CLI11 disabled.
set -euo pipefail
src=$(cd "$1" && pwd)
work=$2
rm -rf "$work"
mkdir -p "$work"
generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
disabled=()
for p in CycloneDDS fcl urdfdom Eigen3 spdlog CLI11 OpenCV GTest; do
  disabled+=(-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON)
done
for type in "" Debug; do
  dir=$work/build-${type:-none}
  echo "== parent with CMAKE_BUILD_TYPE='$type'"
  cmake -S "$src/tests/packaging/subdir_parent" -B "$dir" "${generator[@]}" -DQUIVER_SOURCE_DIR="$src" \
    -DCMAKE_BUILD_TYPE="$type" "${disabled[@]}" >"$dir.log" 2>&1 || { cat "$dir.log"; exit 1; }
  grep "parent:" "$dir.log"
  got=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$dir/CMakeCache.txt")
  if [ "$got" != "$type" ]; then
    echo "FAIL: the cache holds CMAKE_BUILD_TYPE='$got', the parent set '$type'" >&2
    exit 1
  fi
done
# Built in the folder without a build type: no -g, less work than Debug's.
cmake --build "$work/build-none" --target parent_app >"$work/build.log" 2>&1 || { tail -30 "$work/build.log"; exit 1; }
"$work/build-none/parent_app"
echo "PASS"
