#!/usr/bin/env bash
# Entry point for a fresh Debian 12 machine (run as root, or with sudo available):
#   ./run.sh demo    install what is missing, build, run the main demo
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

build() {
  scripts/install-deps.sh
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build
}

case "${1:-}" in
  demo)
    build
    echo "== The Barthel test (seed 000) by five agent processes over Cyclone DDS on loopback, no executive:"
    echo "== the patient leaves mid-sentence once; the Planner is killed with SIGKILL and restarted mid-test"
    isolated build/quiver scenario barthel ${QUIVER_OUT:+--out "$QUIVER_OUT"}
    ;;
  test)
    build
    isolated ctest --test-dir build --output-on-failure -j "$(nproc)"
    scripts/fuzz.sh "${QUIVER_FUZZ_SECONDS:-30}"
    ;;
  build)
    build
    ;;
  *)
    echo "usage: $0 demo|test|build" >&2
    exit 2
    ;;
esac
