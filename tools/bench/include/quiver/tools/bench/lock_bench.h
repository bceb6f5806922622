#pragma once
// The lock benchmark (`quiver bench locks`): the latency of acquiring a lock, in the simulator
// and over DDS on loopback.

#include <cstdint>

namespace quiver::tools::bench {

struct LockBench {
  int agents = 3;             ///< DDS: agents, each a replica of this process with its lock manager
  int rounds = 300;           ///< DDS: acquisitions measured
  std::uint32_t domain = 78;  ///< DDS: the domain they join
};

/// Prints two JSON lines on stdout: the acquire latency in the simulator (8 agents, seed 1,
/// 0.1-2 ms network delay), then over DDS (`agents` replicas in this process, one acquiring and
/// releasing `rounds` times; "null" when the replicas cannot be made).
/// @pre b.agents >= 2, b.rounds >= 1.
/// @returns the exit status: 0, or 1 when the DDS part could not run.
int run_lock_bench(const LockBench& b);

}  // namespace quiver::tools::bench
