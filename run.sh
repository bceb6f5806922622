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
    echo "== 16 agents, random graph churn from all of them at once, 20% loss, duplication,"
    echo "== reordering, partitions and kill -9 crashes; then heal and check convergence"
    build/quiver sim --agents 16 --steps 2000 --seed "${QUIVER_SEED:-1}" \
      --loss 0.2 --dup 0.05 --reorder --partitions --crashes --verbose
    echo
    scripts/demo-dds.sh
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
