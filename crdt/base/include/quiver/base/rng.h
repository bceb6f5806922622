#pragma once
/// @file
/// The one seeded random source: xoshiro256** seeded through splitmix64. Its own distribution
/// helpers (not <random>'s, whose output differs between standard libraries), so a seed replays
/// exactly on every platform.
///
/// Threading: an Rng has no synchronization; one thread uses it at a time (fork() one per
/// thread or sub-system). Nothing here throws.

#include <cstdint>
#include <vector>

namespace quiver::inline base {

class Rng {
 public:
  /// A generator whose whole sequence is determined by `seed`.
  explicit Rng(std::uint64_t seed) : seed_(seed) {
    std::uint64_t x = seed;
    for (auto& s : s_) {
      x += 0x9e3779b97f4a7c15ULL;
      std::uint64_t z = x;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      s = z ^ (z >> 31);
    }
  }
  /// @returns the seed it was constructed with.
  std::uint64_t seed() const { return seed_; }

  /// @returns the next 64 uniformly random bits.
  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  /// Uniform in [0, n), n > 0 (Lemire's multiply-shift; bias below 2^-32 for the n we use).
  /// @pre n > 0 (below(0) returns 0).
  std::uint64_t below(std::uint64_t n) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(next()) * n) >> 64);
  }
  /// Uniform in [lo, hi].
  /// @pre lo <= hi, and [lo, hi] is not the whole int64 range (that returns lo).
  std::int64_t range(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(below(static_cast<std::uint64_t>(hi - lo) + 1));
  }
  /// Uniform in [0, 1).
  /// @returns a multiple of 2^-53.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// @returns true with probability `p` (never for p <= 0, always for p >= 1).
  bool chance(double p) { return uniform() < p; }
  /// @returns a uniformly chosen element of `v`. @pre !v.empty().
  template <class T>
  const T& pick(const std::vector<T>& v) {
    return v[below(v.size())];
  }
  /// Shuffles `v` uniformly (Fisher-Yates).
  template <class T>
  void shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(i)]);
  }
  /// An independent generator derived from this one (for sub-systems).
  /// @returns Rng(next()): advances this generator by one draw.
  Rng fork() { return Rng(next()); }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t seed_;
  std::uint64_t s_[4];
};

}  // namespace quiver
