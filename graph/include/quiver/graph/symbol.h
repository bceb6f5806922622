#pragma once
/// @file
/// Interned strings for attribute names and node/edge types. A Symbol is a small index into a
/// process-wide table; comparisons that must be deterministic across processes use the string
/// (`str()`), never the index, because indices depend on interning order.
///
/// Threading: the table is process-wide and thread-safe; every member may be called from any
/// thread. Symbols themselves are plain values.

#include <compare>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "quiver/base/result.h"

namespace quiver::graph {

class Symbol {
 public:
  Symbol() = default;
  /// Interns `name` (thread-safe). The empty string is the null symbol.
  /// @throws std::length_error when the process's table of names is full
  ///         (limits::kMaxSymbols names or limits::kMaxSymbolBytes of text); make() reports that
  ///         as a value instead.
  explicit Symbol(std::string_view name);
  /// Interns `name`, or kTooLarge when the table is full. Thread-safe.
  /// @returns the symbol (the null symbol for ""), or kTooLarge naming the limits.
  static Result<Symbol> make(std::string_view name);
  /// The symbol of an already interned name, or the null symbol: never adds to the table.
  /// Thread-safe, allocation-free.
  static Symbol find(std::string_view name);
  /// How many names this process has interned (the null symbol excluded). Thread-safe.
  static std::size_t interned_count();
  /// @returns the symbol with table index `index`, unchecked (see index()).
  /// @pre `index` came from index() of a symbol of this process; another index reads as
  ///      "<bad-symbol>".
  static Symbol from_index(std::uint32_t index) {
    Symbol s;
    s.index_ = index;
    return s;
  }

  /// The interned text; valid for the life of the process. Thread-safe.
  const std::string& str() const;
  /// @returns the table index: cheap and unique within this process, meaningless in another.
  std::uint32_t index() const { return index_; }
  /// A hash of the text: the same in every process (unlike the index). Thread-safe.
  std::uint64_t stable_hash() const;
  /// @returns true for the null symbol (the empty name).
  bool is_null() const { return index_ == 0; }

  /// @returns true if both name the same text (within one process: the same index).
  friend bool operator==(Symbol a, Symbol b) { return a.index_ == b.index_; }

 private:
  std::uint32_t index_ = 0;
};

/// Deterministic order of symbols: by text. Thread-safe.
/// @returns true if `a`'s text sorts before `b`'s.
inline bool text_less(Symbol a, Symbol b) { return !(a == b) && a.str() < b.str(); }

/// Well-known symbols, interned on first use (which throws std::length_error, as Symbol(), only
/// if the table is already full then).
namespace symbols {
/// The edge type of kinematic (rigid transform) edges. Thread-safe.
/// @returns the symbol of "RT".
Symbol rt();
/// The attribute an RT edge's change events name when its pose changed. Thread-safe.
/// @returns the symbol of "pose".
Symbol pose();
}  // namespace symbols

}  // namespace quiver::graph

template <>
struct std::hash<quiver::graph::Symbol> {
  /// @returns the symbol's stable_hash(). Thread-safe.
  std::size_t operator()(quiver::graph::Symbol s) const noexcept { return s.stable_hash(); }
};
