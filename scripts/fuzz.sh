#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for a while, starting from
# seed inputs made of real deltas, CDR samples and world files. Exits non-zero on any finding (crash,
# sanitizer report, leak, out-of-memory, invariant violation); the failing input is kept under
# build-fuzz/findings/.
#   scripts/fuzz.sh [seconds-per-target]   (default 30; or QUIVER_FUZZ_SECONDS)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-${QUIVER_FUZZ_SECONDS:-30}}"
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ is missing (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DQUIVER_BUILD_FUZZERS=ON -DQUIVER_SANITIZE=ON >/dev/null
dds_targets="dds_summary dds_delta dds_pull dds_state dds_bye"
cmake --build build-fuzz --target graph_delta_fuzzer replication_samples_fuzzer world_file_fuzzer grammar_file_fuzzer \
  dsr_file_fuzzer agm_file_fuzzer mission_file_fuzzer store_record_fuzzer \
  $(for t in $dds_targets; do printf '%s_fuzzer ' "$t"; done) fuzz_smoke_test
corpus=build-fuzz/corpus
mkdir -p "$corpus"/{delta,samples,world,grammar,dsr,agm,mission,store} build-fuzz/findings
for t in $dds_targets; do mkdir -p "$corpus/$t"; done
# Seed inputs: the smoke test writes the real inputs it mutates (the CORTEX and AGM worlds: the
# interop test fixtures).
QUIVER_FUZZ_CORPUS="$corpus" build-fuzz/tests/fuzz_smoke_test --gtest_filter='*' >/dev/null
status=0
for t in delta:graph_delta samples:replication_samples world:world_file grammar:grammar_file \
         dsr:dsr_file agm:agm_file mission:mission_file store:store_record \
         $(for t in $dds_targets; do printf '%s:%s ' "$t" "$t"; done); do
  dir="${t%%:*}"
  bin="build-fuzz/tests/${t#*:}_fuzzer"
  echo "fuzz.sh: ${t#*:} for ${seconds}s"
  if ! (cd build-fuzz/findings && "../../$bin" "../../$corpus/$dir" -max_total_time="$seconds" \
        -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 2>"${t#*:}.log"); then
    echo "fuzz.sh: FINDING in ${t#*:}: see build-fuzz/findings/${t#*:}.log" >&2
    tail -40 "build-fuzz/findings/${t#*:}.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units" "build-fuzz/findings/${t#*:}.log" | sed "s/^/  /"
  fi
done
exit $status
