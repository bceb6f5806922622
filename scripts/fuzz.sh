#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for a while, starting from
# seed inputs made of real deltas, CDR samples and world files. Exits non-zero on any finding (crash,
# sanitizer report, leak, out-of-memory, invariant violation); the failing input is kept under
# build-fuzz/findings/.
#   scripts/fuzz.sh [seconds-per-target]   (default 30; or QUIVER_FUZZ_SECONDS)
#   scripts/fuzz.sh --build-only           only the build (./run.sh test runs it beside the tests)
# Targets run QUIVER_FUZZ_JOBS at a time (default: the number of cores), each for the full time.
set -euo pipefail
cd "$(dirname "$0")/.."
build_only=false
if [ "${1:-}" = "--build-only" ]; then
  build_only=true
  shift
fi
seconds="${1:-${QUIVER_FUZZ_SECONDS:-30}}"
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ is missing (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
# -O1 with line tables only: what libFuzzer's docs suggest for sanitizer builds, and a quicker
# build than -O2 -g; stack traces still name files and lines. No unity build: every library file
# compiles on its own here (the main build batches them), so a missing #include still shows.
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  -DQUIVER_BUILD_FUZZERS=ON -DQUIVER_SANITIZE=ON -DQUIVER_UNITY_BUILD=OFF >/dev/null
dds_targets="dds_summary dds_delta dds_pull dds_state dds_bye"
# Seed inputs: the smoke test writes the real inputs it mutates (the CORTEX and AGM worlds: the
# interop test fixtures). The one the main build made (./run.sh test builds it first) serves: it
# is the same source; without it, it is built here too (it links the simulator).
smoke=build/tests/fuzz_smoke_test
[ -x "$smoke" ] || smoke=build-fuzz/tests/fuzz_smoke_test
cmake --build build-fuzz --target graph_delta_fuzzer replication_samples_fuzzer world_file_fuzzer grammar_file_fuzzer \
  dsr_file_fuzzer agm_file_fuzzer mission_file_fuzzer schema_file_fuzzer store_record_fuzzer recording_file_fuzzer \
  $(for t in $dds_targets; do printf '%s_fuzzer ' "$t"; done) \
  $([ "$smoke" = build-fuzz/tests/fuzz_smoke_test ] && echo fuzz_smoke_test)
if $build_only; then exit 0; fi
corpus=build-fuzz/corpus
mkdir -p "$corpus"/{delta,samples,world,grammar,dsr,agm,mission,schema,store,recording} build-fuzz/findings
for t in $dds_targets; do mkdir -p "$corpus/$t"; done
QUIVER_FUZZ_CORPUS="$corpus" "$smoke" --gtest_filter='*' >/dev/null
jobs="${QUIVER_FUZZ_JOBS:-$(nproc)}"
# One target for $seconds; its log in build-fuzz/findings/NAME.log; non-zero on a finding.
fuzz_one() {
  local dir="${1%%:*}" name="${1#*:}"
  if ! (cd build-fuzz/findings && "../../build-fuzz/tests/${name}_fuzzer" "../../$corpus/$dir" \
        -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 \
        2>"$name.log"); then
    echo "fuzz.sh: FINDING in $name: see build-fuzz/findings/$name.log" >&2
    tail -40 "build-fuzz/findings/$name.log" >&2
    return 1
  fi
  echo "fuzz.sh: $name for ${seconds}s: $(grep -E 'stat::number_of_executed_units' \
    "build-fuzz/findings/$name.log" | sed 's/.*: *//') inputs, no finding"
}
status=0
running=0
for t in delta:graph_delta samples:replication_samples world:world_file grammar:grammar_file \
         dsr:dsr_file agm:agm_file mission:mission_file schema:schema_file store:store_record recording:recording_file \
         $(for t in $dds_targets; do printf '%s:%s ' "$t" "$t"; done); do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || status=1
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || status=1
  running=$((running - 1))
done
exit $status
