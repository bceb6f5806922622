#!/usr/bin/env bash
# Installs every Debian 12 package that Quiver's build, tests, benchmarks and fuzzers need.
#   scripts/install-deps.sh          everything
#   scripts/install-deps.sh --demo   only what `./run.sh demo` needs (quiver-barthel: the agent
#                                    libraries, Cyclone DDS, three OpenCV modules, espeak-ng)
# Idempotent: does nothing when everything is present. Must run as root (or via sudo).
set -euo pipefail

demo_packages=(
  build-essential cmake ninja-build pkg-config
  cyclonedds-dev cyclonedds-tools nlohmann-json3-dev libcli11-dev libspdlog-dev libpugixml-dev liblmdb-dev libssl-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev espeak-ng
  iproute2
)
packages=(
  build-essential cmake ninja-build pkg-config git
  clang libclang-rt-14-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  cyclonedds-dev cyclonedds-tools
  libeigen3-dev libfcl-dev liburdfdom-dev liburdfdom-headers-dev libconsole-bridge-dev
  libtf2-dev
  nlohmann-json3-dev libcli11-dev libspdlog-dev libpugixml-dev liblmdb-dev libssl-dev
  espeak-ng libopencv-dev
  libcpp-httplib-dev libjs-d3 libjs-three libgraphviz-dev
  chromium chromium-driver python3-selenium
  iproute2 procps python3
  pybind11-dev python3-dev python3-pytest python3-numpy python3-pytest-benchmark
  python3-matplotlib
)

case "${1:-}" in
  --demo) packages=("${demo_packages[@]}") ;;
  "") ;;
  *) echo "usage: $0 [--demo]" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
echo "install-deps: apt-get update" >&2
$SUDO apt-get update -qq
# -q (not -qq): a line per package fetched, unpacked and set up, as progress.
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
