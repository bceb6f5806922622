#pragma once
// Seeds for randomized tests: every test prints the seed it used; QUIVER_SEED=<n> replays one.
// A count that would run nothing (QUIVER_SEEDS=0, a typo) fails the test instead of passing it.

#include <gtest/gtest.h>

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

/// A positive count from the environment variable `var`, else `fallback`; anything else fails
/// the running test (and 0 is returned, so nothing runs, and the failure says why).
inline int count_from_env(const char* var, int fallback) {
  const char* env = std::getenv(var);
  if (env == nullptr) return fallback;
  char* end = nullptr;
  long v = std::strtol(env, &end, 10);
  if (end == env || *end != '\0' || v <= 0 || v > 100'000'000) {
    ADD_FAILURE() << var << "=" << env << " must be a positive count: a test that runs nothing proves nothing";
    return 0;
  }
  return static_cast<int>(v);
}

/// How many seeds a property test runs: QUIVER_SEEDS if set (1 when QUIVER_SEED replays).
inline int seed_count(int fallback) {
  if (std::getenv("QUIVER_SEED")) return 1;
  return count_from_env("QUIVER_SEEDS", fallback);
}

}  // namespace quiver::testing
