#pragma once
// The benchmarks' statistics under their old names, for tools/reaction_bench.cc: they are
// quiver_bench's (quiver/tools/bench/bench_stats.h).

#include "quiver/tools/bench/bench_stats.h"

namespace quiver::tools {

using bench::median;
using bench::Percentiles;
using bench::round_to;

}  // namespace quiver::tools
