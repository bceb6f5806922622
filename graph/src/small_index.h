#pragma once
// Private: where keys sit in a vector its owner keeps, for the small per-commit tables whose
// contents are kept from one commit to the next (their capacity reused: no allocation).

#include <cstddef>
#include <unordered_map>

namespace quiver::graph {

/// Positions of keys in a vector the caller keeps (keys at 0..n-1, appended in order): found by
/// a scan while there are few, through a hash index built once there are many.
template <class Key>
class SmallIndex {
 public:
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
  /// The position of `k` among the first `n`, or npos; key_of(i) is the key at position i.
  template <class KeyOf>
  std::size_t find(const Key& k, std::size_t n, KeyOf key_of) const {
    if (!hashed_.empty()) {
      auto it = hashed_.find(k);
      return it == hashed_.end() ? npos : it->second;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (key_of(i) == k) return i;
    return npos;
  }
  /// `k` was appended at position n - 1.
  template <class KeyOf>
  void added(const Key& k, std::size_t n, KeyOf key_of) {
    if (!hashed_.empty()) {
      hashed_.emplace(k, n - 1);
    } else if (n > kScan) {
      for (std::size_t i = 0; i < n; ++i) hashed_.emplace(key_of(i), i);
    }
  }
  /// Forgets every key (a large table's hash index is not kept).
  void clear() {
    if (!hashed_.empty()) hashed_ = {};
  }

 private:
  static constexpr std::size_t kScan = 16;
  std::unordered_map<Key, std::size_t> hashed_;
};

}  // namespace quiver::graph
