#pragma once
/// @file
/// A fast, deterministic, platform-independent 128-bit streaming hash for state digests, and
/// 64-bit mixing for hash tables. Not cryptographic.
///
/// Threading: plain values and pure functions; thread-safe on distinct Hashers.

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace quiver::inline base {

/// splitmix64's finaliser: a bijective 64-bit mix.
/// @returns the mixed value (mix64(0) is 0).
constexpr std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/// @returns a hash of `seed` followed by `v` (order matters), for composite hash-table keys.
constexpr std::uint64_t hash_combine(std::uint64_t seed, std::uint64_t v) {
  return mix64(seed ^ (v + 0x9e3779b97f4a7c15ULL + (seed << 6) + (seed >> 2)));
}

/// 128-bit digest. Digests of independent parts can be summed (mod 2^128) to get an
/// order-independent digest of a set.
struct Digest128 {
  std::uint64_t hi = 0;
  std::uint64_t lo = 0;

  friend bool operator==(const Digest128&, const Digest128&) = default;
  /// Adds `o` modulo 2^128 (commutative, so set digests do not depend on order).
  /// @returns *this.
  Digest128& operator+=(const Digest128& o) {
    std::uint64_t old = lo;
    lo += o.lo;
    hi += o.hi + (lo < old ? 1 : 0);
    return *this;
  }
  /// @returns 32 lowercase hex digits: hi then lo.
  std::string hex() const {
    static const char* kDigits = "0123456789abcdef";
    std::string s(32, '0');
    for (int i = 0; i < 16; ++i) {
      s[15 - i] = kDigits[(hi >> (4 * i)) & 0xf];
      s[31 - i] = kDigits[(lo >> (4 * i)) & 0xf];
    }
    return s;
  }
};

/// Streaming hasher with two independent 64-bit lanes.
class Hasher {
 public:
  Hasher() = default;
  /// A hasher whose digests depend on `seed` (distinct seeds separate digest domains).
  explicit Hasher(std::uint64_t seed) : a_(mix64(seed ^ 0x243f6a8885a308d3ULL)), b_(mix64(seed + 7)) {}

  /// Feeds one 64-bit word. @returns *this, for chaining.
  Hasher& u64(std::uint64_t v) {
    a_ = mix64(a_ ^ (v * 0x9e3779b97f4a7c15ULL)) + 0x632be59bd9b4e019ULL;
    b_ = mix64((b_ + v) * 0xc2b2ae3d27d4eb4fULL) ^ 0x165667b19e3779f9ULL;
    ++n_;
    return *this;
  }
  /// Feeds `v`'s two's-complement bits, as u64(). @returns *this.
  Hasher& i64(std::int64_t v) { return u64(static_cast<std::uint64_t>(v)); }
  /// Feeds `v`'s IEEE-754 bits (so 0.0 and -0.0 differ). @returns *this.
  Hasher& f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    return u64(bits);
  }
  /// Feeds `v`'s IEEE-754 bits as one word. @returns *this.
  Hasher& f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    return u64(bits);
  }
  /// Feeds the length, then the bytes in 8-byte little-endian words (length-prefixed, so
  /// concatenations do not collide). @pre `data` points to `n` readable bytes. @returns *this.
  Hasher& bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    u64(n);
    while (n >= 8) {
      std::uint64_t w;
      std::memcpy(&w, p, 8);
      u64(w);
      p += 8;
      n -= 8;
    }
    if (n > 0) {
      std::uint64_t w = 0;
      std::memcpy(&w, p, n);
      u64(w);
    }
    return *this;
  }
  /// Feeds a string as bytes(). @returns *this.
  Hasher& str(std::string_view s) { return bytes(s.data(), s.size()); }

  /// @returns the 128-bit digest of everything fed so far (the hasher may go on).
  Digest128 digest() const { return Digest128{mix64(b_ ^ n_), mix64(a_ + n_ * 31)}; }
  /// @returns a 64-bit hash of everything fed so far (not a half of digest()).
  std::uint64_t h64() const { return mix64(a_ ^ mix64(b_)); }

 private:
  std::uint64_t a_ = 0x6a09e667f3bcc908ULL;
  std::uint64_t b_ = 0xbb67ae8584caa73bULL;
  std::uint64_t n_ = 0;
};

/// FNV-1a 64 of a string: used to derive an agent id from its name.
/// @returns the standard FNV-1a 64-bit hash of the bytes of `s`.
constexpr std::uint64_t fnv1a64(std::string_view s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (char c : s) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace quiver
