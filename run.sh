#!/usr/bin/env bash
# Entry point for a fresh Debian 12 machine (run as root, or with sudo available):
#   ./run.sh demo    install what the demo needs, build only its executable, run the main demo
#   ./run.sh test    install what is missing, build, run every test (unit, property, simulator,
#                    fuzzing)
#   ./run.sh build   install what is missing and build only
set -euo pipefail
cd "$(dirname "$0")"

# Runs a command in a private network namespace holding only loopback, when the kernel lets us:
# then nothing a test does can leave this machine, whatever its DDS configuration.
isolated() {
  if unshare --net true 2>/dev/null; then
    unshare --net sh -c 'ip link set lo up && exec "$@"' sh "$@"
  else
    "$@"
  fi
}

# The CMake options of the full build and of the demo's (the arrays everything and demo_only).
source scripts/build-options.sh

build() {
  scripts/install-deps.sh
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${everything[@]}" >/dev/null
  cmake --build build
}

# "== [step/3] what (time since the start)" for the demo's first run.
started=$SECONDS
step() { echo "== [$1/3] $2 ($((SECONDS - started)) s so far)"; }

case "${1:-}" in
  demo)
    step 1 "installing what the demo needs (scripts/install-deps.sh --demo)"
    scripts/install-deps.sh --demo
    step 2 "building quiver-barthel, the demo's executable, and only what it links"
    cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${demo_only[@]}" >/dev/null
    cmake --build build --target quiver-barthel
    step 3 "running the demo"
    echo "== The Barthel test (seed 000) by five agent processes over Cyclone DDS on loopback, no executive:"
    echo "== the patient leaves mid-sentence once; the Planner is killed with SIGKILL and restarted mid-test"
    isolated build/quiver-barthel scenario barthel ${QUIVER_OUT:+--out "$QUIVER_OUT"}
    ;;
  test)
    build
    # The fuzzers' sanitizer build (clang) runs beside the tests at the lowest priority: most
    # tests wait on DDS, timers and child processes, and it takes only the CPU they leave idle.
    nice -n 19 scripts/fuzz.sh --build-only >build/fuzz-build.log 2>&1 &
    fuzz_build=$!
    status=0
    isolated ctest --test-dir build --output-on-failure -j "$(nproc)" || status=$?
    if ! wait "$fuzz_build"; then
      echo "run.sh: the fuzzers' build failed (build/fuzz-build.log):" >&2
      tail -40 build/fuzz-build.log >&2
      exit 1
    fi
    if [ "$status" -ne 0 ]; then exit "$status"; fi
    scripts/fuzz.sh "${QUIVER_FUZZ_SECONDS:-10}"
    ;;
  build)
    build
    ;;
  *)
    echo "usage: $0 demo|test|build" >&2
    exit 2
    ;;
esac
