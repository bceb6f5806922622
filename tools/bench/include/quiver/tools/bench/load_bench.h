#pragma once
// The large-transaction benchmark (`quiver bench load`): an RT chain built, committed, decoded
// and merged in one transaction, and the same chain loaded from a world file.

namespace quiver::tools::bench {

struct LoadBench {
  int frames = 100'000;  ///< frames of the chain
  int runs = 5;          ///< medians over this many runs are reported
};

/// One transaction that builds an RT chain of `frames` frames (each a new node under the last),
/// committed and encoded; a second replica decodes and merges it; then the same chain as a JSON
/// world file is loaded into a third. Prints one JSON line on stdout: medians over the runs, in
/// milliseconds.
/// @pre b.frames >= 2, b.runs >= 1.
/// @returns the exit status: 0 when every replica ends as the first, 1 when one differs, 2 when
/// the chain cannot be built or committed.
int run_load_bench(const LoadBench& b);

}  // namespace quiver::tools::bench
