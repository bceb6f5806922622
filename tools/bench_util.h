#pragma once
// The benchmarks' clock and transforms tree under their old names, for quiver_bench_tf2
// (tools/bench_tf2.cc): they are quiver_bench's (quiver/tools/bench/bench_util.h).

#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools {

using bench::bench_pose;
using bench::BenchPose;
using bench::seconds_since;

}  // namespace quiver::tools
