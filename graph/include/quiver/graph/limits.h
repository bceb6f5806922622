#pragma once
/// @file
/// The one table of size limits for graph data. Every producer (a local commit, a world file)
/// and every decoder of untrusted bytes applies these same numbers, so that whatever a local
/// commit accepts, every peer's decoder accepts, and nothing a decoder refuses can be committed.
///
/// Threading: the functions here are pure and thread-safe; they return errors as values.

#include <cstdint>
#include <string_view>

#include "quiver/base/result.h"

namespace quiver::graph {

class Value;

namespace limits {
/// Payload of one attribute value: a string's or byte array's length, a vector's elements times
/// their size.
inline constexpr std::uint64_t kMaxValueBytes = 64ull << 20;
/// A node name, a node type, an edge type, an attribute name, a rule or variable name.
inline constexpr std::uint64_t kMaxNameBytes = 4096;
/// The estimated encoding of one transaction (one delta), names and values included.
inline constexpr std::uint64_t kMaxDeltaBytes = 96ull << 20;
/// Distinct replicas or distinct names in one encoded message.
inline constexpr std::uint64_t kMaxTable = 1u << 20;
/// Distinct names (types, attribute names) one process interns, and their total text.
inline constexpr std::uint64_t kMaxSymbols = 1u << 20;
inline constexpr std::uint64_t kMaxSymbolBytes = 64ull << 20;
}  // namespace limits

/// True if `s` is well-formed UTF-8 (no overlong forms, no surrogates, at most U+10FFFF).
/// @returns true for the empty string.
bool valid_utf8(std::string_view s);

/// Checks a name against the table: non-empty, at most limits::kMaxNameBytes, valid UTF-8.
/// @param what  names the name in the error, e.g. "create_node(): the type".
/// @returns kInvalidArgument (empty, not UTF-8) or kTooLarge, with `what` and the name quoted
///          (shortened when long).
Status check_name(std::string_view what, std::string_view name);

/// Checks a value's payload against limits::kMaxValueBytes (kTooLarge naming `what`).
/// @returns kTooLarge if Value::payload_bytes() exceeds the limit; OK otherwise.
Status check_value(std::string_view what, const Value& v);

/// check_name() of an attribute's name and check_value() of its value, as `fn` (e.g. "set()")
/// names them in errors ("set(): attribute 'x' holds ..."); builds no message when both pass.
Status check_attribute(std::string_view fn, std::string_view name, const Value& v);

/// A name shortened for an error message ("abc…(5000 bytes)").
/// @returns `name` in single quotes; past 40 bytes, its first 40 bytes then "...(<n> bytes)".
std::string quote_name(std::string_view name);

}  // namespace quiver::graph
