#pragma once
/// @file
/// The scripts the benchmarks run, embedded in the binary so that an installed `quiver` has them
/// too (tools/bench/CMakeLists.txt): "team_bench.sh" and "netns.sh" (`quiver bench team`),
/// "yjs_crdt.js" (the CRDT workload in Yjs) and "plot_bench.py" (the page of `quiver bench all`).
#include <string_view>

namespace quiver::tools::bench {

/// The embedded file `name`, or "".
std::string_view embedded_file(std::string_view name);

}  // namespace quiver::tools::bench
