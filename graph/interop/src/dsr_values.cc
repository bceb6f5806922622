// Reading CORTEX DSR JSON values: numbers in every form files use, attribute values with a type
// code or typed by their content, attribute entries in every layout, and ids.

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#include "dsr_json.h"
#include "plan.h"
#include "quiver/graph/limits.h"
#include "text_values.h"

namespace quiver::interop {
namespace internal {

/// A JSON pointer's reference token (RFC 6901: '~' as ~0, '/' as ~1).
std::string token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

// ------------------------------------------------------------------------------ JSON numbers

/// A number or a decimal string (',' accepted as the decimal point, as CORTEX's reader does).
bool as_double(const json& j, double& out) {
  if (j.is_number()) {
    out = j.get<double>();
    return std::isfinite(out);
  }
  return j.is_string() && internal::parse_decimal(j.get_ref<const std::string&>(), out, /*comma=*/true);
}

/// An integer, a number with a fraction (rounded, like Qt's QVariant::toInt; `rounded` tells),
/// or the same as a string.
bool as_integer(const json& j, std::int64_t& out, bool& rounded) {
  rounded = false;
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(INT64_MAX)) return false;
    out = static_cast<std::int64_t>(u);
    return true;
  }
  if (j.is_number_integer()) {
    out = j.get<std::int64_t>();
    return true;
  }
  if (j.is_string() && internal::parse_int64(j.get_ref<const std::string&>(), out)) return true;
  double d;
  if (!as_double(j, d) || std::fabs(d) > 9.0e18) return false;
  out = std::llround(d);
  rounded = static_cast<double>(out) != d;
  return true;
}

/// A non-negative integer, or digits in a string (CORTEX writes uint64 values as strings).
bool as_uint64(const json& j, std::uint64_t& out) {
  if (j.is_number_unsigned()) {
    out = j.get<std::uint64_t>();
    return true;
  }
  if (j.is_number_integer()) {
    const auto i = j.get<std::int64_t>();
    if (i < 0) return false;
    out = static_cast<std::uint64_t>(i);
    return true;
  }
  return j.is_string() && internal::parse_uint64(j.get_ref<const std::string&>(), out);
}

/// The numbers of an array (numbers or numeric strings), or of a string of numbers separated by
/// white space (the oldest files).
bool as_doubles(const json& j, std::vector<double>& out) {
  out.clear();
  if (j.is_array()) {
    out.reserve(j.size());
    for (const json& e : j) {
      double d;
      if (!as_double(e, d)) return false;
      out.push_back(d);
    }
    return true;
  }
  if (!j.is_string()) return false;
  const std::string& s = j.get_ref<const std::string&>();
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) ++i;
    std::size_t k = i;
    while (k < s.size() && s[k] != ' ' && s[k] != '\t' && s[k] != '\n' && s[k] != '\r') ++k;
    if (k == i) break;
    double d;
    if (!internal::parse_decimal(std::string_view(s).substr(i, k - i), d, true)) return false;
    out.push_back(d);
    i = k;
  }
  return true;
}

}  // namespace internal

namespace {

using graph::Value;
using graph::ValueType;
using internal::Attrs;
using internal::as_double;
using internal::as_doubles;
using internal::as_integer;
using internal::as_uint64;
using internal::json;
using internal::malformed;

bool float_range(double d) { return std::fabs(d) <= FLT_MAX; }

template <std::size_t N>
bool as_floats(const json& j, std::array<float, N>& out) {
  std::vector<double> d;
  if (!as_doubles(j, d) || d.size() != N) return false;
  for (std::size_t i = 0; i < N; ++i) {
    if (!float_range(d[i])) return false;
    out[i] = static_cast<float>(d[i]);
  }
  return true;
}

// ------------------------------------------------------------------------------ values

constexpr int kCodes = 14;  // 0 string ... 13 vec6f (dsr.h)

/// The value of an attribute with a CORTEX type code. `warn` receives notes (rounding).
Result<Value> typed_value(int code, const json& v, const std::string& where, std::vector<std::string>& warnings) {
  auto bad = [&](const std::string& expect) {
    return malformed(where, "type code " + std::to_string(code) + " expects " + expect);
  };
  // Codes 10 to 13: std::array<float, N>.
  auto fixed = [&]<std::size_t N>() -> Result<Value> {
    std::array<float, N> f;
    if (!as_floats(v, f)) return bad("an array of " + std::to_string(N) + " numbers");
    return Value(f);
  };
  switch (code) {
    case 0:
      if (v.is_string()) return Value(v.get<std::string>());
      if (v.is_number() || v.is_boolean()) return Value(v.dump());  // Qt's toString()
      return bad("a string");
    case 1:
    case 6: {
      std::int64_t i;
      bool rounded;
      if (!as_integer(v, i, rounded)) return bad("an integer");
      if (code == 1) {
        if (i < INT32_MIN || i > INT32_MAX) return bad("an integer in int32 range");
        if (rounded) warnings.push_back(where + ": " + v.dump() + " is not an integer: rounded to " + std::to_string(i));
        return Value::int32(static_cast<std::int32_t>(i));
      }
      // CORTEX writes a uint32 as the int32 of the same bits: a negative value wraps.
      if (i < INT32_MIN || i > static_cast<std::int64_t>(UINT32_MAX)) return bad("an integer in uint32 range");
      if (rounded) warnings.push_back(where + ": " + v.dump() + " is not an integer: rounded to " + std::to_string(i));
      return Value::uint32(static_cast<std::uint32_t>(i < 0 ? i + (std::int64_t{1} << 32) : i));
    }
    case 2: {
      double d;
      if (!as_double(v, d) || !float_range(d)) return bad("a number in float range");
      return Value(static_cast<float>(d));
    }
    case 3: {
      std::vector<double> d;
      if (!as_doubles(v, d)) return bad("an array of numbers");
      graph::FloatVec f;
      f.reserve(d.size());
      for (double x : d) {
        if (!float_range(x)) return bad("an array of numbers in float range");
        f.push_back(static_cast<float>(x));
      }
      return Value(std::move(f));
    }
    case 4:
      if (v.is_boolean()) return Value(v.get<bool>());
      if (v.is_number_integer() && (v.get<std::int64_t>() == 0 || v.get<std::int64_t>() == 1))
        return Value(v.get<std::int64_t>() == 1);
      if (v.is_string()) {
        std::string s = v.get<std::string>();
        for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (s == "true" || s == "1") return Value(true);
        if (s == "false" || s == "0") return Value(false);
      }
      return bad("true or false");
    case 5: {
      if (!v.is_array()) return bad("an array of bytes (0 to 255)");
      graph::Bytes b;
      b.reserve(v.size());
      for (const json& e : v) {
        std::uint64_t x;
        if (!as_uint64(e, x) || x > 255) return bad("an array of bytes (0 to 255)");
        b.push_back(static_cast<std::uint8_t>(x));
      }
      return Value(std::move(b));
    }
    case 7: {
      std::uint64_t x;
      if (!as_uint64(v, x)) return bad("an unsigned integer (or its digits as a string)");
      return Value(x);
    }
    case 8: {
      double d;
      if (!as_double(v, d)) return bad("a number");
      return Value(d);
    }
    case 9: {
      if (!v.is_array()) return bad("an array of unsigned integers");
      graph::UInt64Vec u;
      u.reserve(v.size());
      for (const json& e : v) {
        std::uint64_t x;
        if (!as_uint64(e, x)) return bad("an array of unsigned integers");
        u.push_back(x);
      }
      return Value(std::move(u));
    }
    case 10: return fixed.template operator()<2>();
    case 11: return fixed.template operator()<3>();
    case 12: return fixed.template operator()<4>();
    case 13: return fixed.template operator()<6>();
  }
  return malformed(where, "unknown type code " + std::to_string(code));
}

/// A value without a type code, typed by its content with CORTEX's types: an integer is an int32
/// (a uint64 beyond it; a double below it), a number with a fraction a double, true/false a bool,
/// an array of numbers a float_vec; a string is read as AGM's strings are (an integer, a decimal
/// number or true/false in it take those types), else stays a string.
Result<Value> untyped_value(const json& v, const std::string& where) {
  auto integer = [](std::int64_t i) -> Value {
    if (i >= INT32_MIN && i <= INT32_MAX) return Value::int32(static_cast<std::int32_t>(i));
    if (i >= 0) return Value(static_cast<std::uint64_t>(i));
    return Value(static_cast<double>(i));
  };
  if (v.is_boolean()) return Value(v.get<bool>());
  if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))
    return Value(v.get<std::uint64_t>());
  if (v.is_number_integer()) return integer(v.get<std::int64_t>());
  if (v.is_number_float()) return Value(v.get<double>());
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    std::uint64_t u;
    if (internal::parse_uint64(s, u) && u > static_cast<std::uint64_t>(INT64_MAX)) return Value(u);
    Value typed = internal::typed_by_content(s);
    if (const auto* i = typed.get_if<std::int64_t>()) {
      if (*i < INT32_MIN && *i >= -(std::int64_t{1} << 53)) return Value(static_cast<double>(*i));
      if (*i < INT32_MIN) return Value(s);
      return integer(*i);
    }
    return typed;
  }
  if (v.is_array()) {
    std::vector<double> d;
    if (as_doubles(v, d) && std::all_of(d.begin(), d.end(), float_range))
      return Value(graph::FloatVec(d.begin(), d.end()));
  }
  return malformed(where, "expected a value (a string, number, bool or array of numbers)");
}

/// A type code: a number or its digits as a string.
Result<int> type_code(const json& t, const std::string& where) {
  std::int64_t code = -1;
  if (t.is_number_integer()) code = t.get<std::int64_t>();
  else if (t.is_string() && !internal::parse_int64(t.get_ref<const std::string&>(), code)) code = -1;
  if (code < 0 || code >= kCodes)
    return malformed(where, "unknown type code " + t.dump() + " (CORTEX's codes are 0 to 13)");
  return static_cast<int>(code);
}

/// One attribute: {"type": CODE, "value": V}, or {"value": V} without a code.
Result<Value> attribute_value(const json& a, const std::string& where, std::vector<std::string>& warnings) {
  auto value = a.find("value");
  if (value == a.end()) return malformed(where, "missing \"value\"");
  auto type = a.find("type");
  if (type == a.end() || type->is_null()) return untyped_value(*value, where);
  auto code = type_code(*type, where);
  if (!code.ok()) return code.error();
  return typed_value(*code, *value, where, warnings);
}

}  // namespace

namespace internal {

/// The entries of an "attribute" / "linkAttribute" member: an object name -> {type, value}
/// (with the hand-written {"key": NAME, "value": V} pair of the planner's example worlds), or an
/// array of {"key", "value"[, "type"]}.
Result<std::vector<RawAttr>> raw_attributes(const json& j, const std::string& where) {
  std::vector<RawAttr> out;
  if (j.is_null()) return out;
  if (j.is_object()) {
    const bool key_value_pair = j.contains("key") && j["key"].is_string() && j.contains("value") && !j["value"].is_object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string at = where + "/" + token(it.key());
      if (key_value_pair && (it.key() == "key" || it.key() == "value")) {
        if (it.key() == "key") out.push_back(RawAttr{it.value().get<std::string>(), json{{"value", j["value"]}}, where});
        continue;
      }
      if (!it.value().is_object()) return malformed(at, "expected {\"type\": CODE, \"value\": V}");
      out.push_back(RawAttr{it.key(), it.value(), at});
    }
    return out;
  }
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string at = where + "/" + std::to_string(i);
      const json& e = j[i];
      auto key = e.is_object() ? e.find("key") : e.end();
      if (!e.is_object() || key == e.end() || !key->is_string())
        return malformed(at, "expected {\"key\": NAME, \"value\": V[, \"type\": CODE]}");
      out.push_back(RawAttr{key->get<std::string>(), e, at});
    }
    return out;
  }
  return malformed(where, "expected an object of attributes (or an array of {\"key\", \"value\"})");
}

Result<Attrs> convert(const std::vector<RawAttr>& raw, std::vector<std::string>& warnings) {
  Attrs out;
  out.reserve(raw.size());
  for (const RawAttr& a : raw) {
    if (a.name.empty()) return malformed(a.where, "an attribute with an empty name");
    auto v = attribute_value(a.entry, a.where, warnings);
    if (!v.ok()) return v.error();
    out.emplace_back(a.name, std::move(*v));
  }
  return out;
}

/// A CORTEX id: digits in a string or an unsigned number, as canonical decimal text.
Result<std::string> node_id(const json& j, const std::string& where) {
  std::uint64_t id;
  if (!as_uint64(j, id)) return malformed(where, "expected a CORTEX id (an unsigned integer)");
  return std::to_string(id);
}

}  // namespace internal
}  // namespace quiver::interop
