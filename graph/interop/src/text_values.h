#pragma once
// Private: numbers and values as text, the way both source formats write them, and AGM's
// string attributes typed by their content (docs/interop.md, "Values").

#include <cstdint>
#include <string>
#include <string_view>

#include "quiver/graph/value.h"

namespace quiver::interop::internal {

/// The shortest decimal text that reads back as exactly `v` (std::to_chars).
std::string shortest(double v);
std::string shortest(float v);
/// shortest(v) with ".0" appended when it has no '.' or exponent, so that content typing reads
/// it back as a double and not as an integer ("2.0", "-0.0", "1e+20").
std::string double_text(double v);

/// A pose number (millimetres, radians) as written by the exporters: 15 significant digits, and
/// 0 below 1e-12. Converting Euler angles to a quaternion and back moves the last bits; rounded
/// so, an exported file exports again to the same text (1e-15 relative is far below the
/// precision the formats carry: CORTEX stores floats).
std::string pose_text(double v);

/// The double a number's text reads as (std::from_chars: unlike std::stod, it takes subnormal
/// numbers, which real files hold). 0 for text that is no number.
double read_back(const std::string& text);

/// Whole-string parses: no white space, no '+'. parse_int64 takes -?[0-9]+ in int64 range,
/// parse_uint64 [0-9]+ in uint64 range.
bool parse_int64(std::string_view s, std::int64_t& out);
bool parse_uint64(std::string_view s, std::uint64_t& out);
/// A finite decimal number: -?(d+(.d*)?|.d+)([eE][-+]?d+)?. With `comma`, one ',' may stand for
/// the decimal point (CORTEX's and AGM's readers accept "197,92").
bool parse_decimal(std::string_view s, double& out, bool comma = false);

/// An AGM attribute string typed by its content: an integer in int64 range is an int64, another
/// decimal number a double, "true"/"false" a bool, anything else (an integer beyond int64
/// included) the string itself.
graph::Value typed_by_content(std::string_view s);

/// A value as AGM attribute text. `exact` is set to whether typed_by_content() gives the same
/// value back (false for an int32, a float, a vector, a string that reads as a number...).
std::string value_text(const graph::Value& v, bool& exact);

/// `s` quoted for a message, shortened past `max` bytes.
std::string in_quotes(std::string_view s, std::size_t max = 60);

}  // namespace quiver::interop::internal
