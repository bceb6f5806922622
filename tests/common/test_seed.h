#pragma once
// Seeds for randomized tests: every test prints the seed it used; QUIVER_SEED=<n> replays one.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace quiver::testing {

/// The base seed of a randomized test: QUIVER_SEED if set, else `fallback`. Printed once.
inline std::uint64_t base_seed(const char* test, std::uint64_t fallback) {
  std::uint64_t seed = fallback;
  if (const char* env = std::getenv("QUIVER_SEED")) seed = std::strtoull(env, nullptr, 0);
  std::printf("[seed] %s: base seed %llu (replay with QUIVER_SEED=%llu)\n", test,
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed));
  return seed;
}

/// How many seeds a property test runs: QUIVER_SEEDS if set (1 when QUIVER_SEED replays).
inline int seed_count(int fallback) {
  if (std::getenv("QUIVER_SEED")) return 1;
  if (const char* env = std::getenv("QUIVER_SEEDS")) return std::atoi(env);
  return fallback;
}

}  // namespace quiver::testing
