// Numbers and values as text the way both source formats write them, and AGM's string attributes typed by their
// content.
#include "text_values.h"

#include <charconv>
#include <cmath>

namespace quiver::interop::internal {

using graph::Value;
using graph::ValueType;

std::string shortest(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string shortest(float v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string double_text(double v) {
  std::string s = shortest(v);
  if (std::isfinite(v) && s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string pose_text(double v) {
  if (!(std::fabs(v) >= 1e-12)) return "0";
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 15);
  std::string s(buf, r.ptr);
  // Near the largest double, rounding to 15 digits can step past it: keep every digit then.
  double back;
  if (std::from_chars(s.data(), s.data() + s.size(), back).ec != std::errc()) return shortest(v);
  return s;
}

double read_back(const std::string& text) {
  double d = 0.0;
  std::from_chars(text.data(), text.data() + text.size(), d);
  return d;
}

namespace {
bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}
}  // namespace

bool parse_int64(std::string_view s, std::int64_t& out) {
  const bool neg = !s.empty() && s[0] == '-';
  if (!all_digits(neg ? s.substr(1) : s)) return false;
  auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parse_uint64(std::string_view s, std::uint64_t& out) {
  if (!all_digits(s)) return false;
  auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parse_decimal(std::string_view s, double& out, bool comma) {
  std::string t(s);
  std::size_t i = 0;
  if (i < t.size() && t[i] == '-') ++i;
  std::size_t int_digits = 0, frac_digits = 0;
  while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i, ++int_digits;
  if (i < t.size() && (t[i] == '.' || (comma && t[i] == ','))) {
    t[i] = '.';
    ++i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i, ++frac_digits;
  }
  if (int_digits + frac_digits == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t exp_digits = 0;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i, ++exp_digits;
    if (exp_digits == 0) return false;
  }
  if (i != t.size()) return false;
  auto r = std::from_chars(t.data(), t.data() + t.size(), out);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(out);
}

Value typed_by_content(std::string_view s) {
  if (s == "true") return Value(true);
  if (s == "false") return Value(false);
  std::int64_t i;
  if (parse_int64(s, i)) return Value(i);
  const bool integer = !s.empty() && (s[0] == '-' ? all_digits(s.substr(1)) : all_digits(s));
  double d;
  if (!integer && parse_decimal(s, d)) return Value(d);
  return Value(std::string(s));
}

namespace {
template <class Vec>
std::string join(const Vec& v) {
  std::string out;
  for (const auto& x : v) {
    if (!out.empty()) out += ' ';
    if constexpr (std::is_floating_point_v<std::decay_t<decltype(x)>>)
      out += shortest(x);
    else
      out += std::to_string(x);
  }
  return out;
}
}  // namespace

std::string value_text(const Value& v, bool& exact) {
  exact = false;
  switch (v.type()) {
    case ValueType::kString: {
      const std::string& s = *v.get_if<std::string>();
      exact = typed_by_content(s) == v;
      return s;
    }
    case ValueType::kBool:
      exact = true;
      return *v.get_if<bool>() ? "true" : "false";
    case ValueType::kInt64:
      exact = true;
      return std::to_string(*v.get_if<std::int64_t>());
    case ValueType::kInt32: return std::to_string(*v.get_if<std::int32_t>());
    case ValueType::kUInt32: return std::to_string(*v.get_if<std::uint32_t>());
    case ValueType::kUInt64: return std::to_string(*v.get_if<std::uint64_t>());
    case ValueType::kDouble: {
      const double d = *v.get_if<double>();
      exact = std::isfinite(d);
      return double_text(d);
    }
    case ValueType::kFloat: {
      std::string s = shortest(*v.get_if<float>());
      if (std::isfinite(*v.get_if<float>()) && s.find_first_of(".e") == std::string::npos) s += ".0";
      return s;
    }
    case ValueType::kBytes: return join(*v.get_if<graph::Bytes>());
    case ValueType::kFloatVec: return join(*v.get_if<graph::FloatVec>());
    case ValueType::kDoubleVec: return join(*v.get_if<graph::DoubleVec>());
    case ValueType::kUInt64Vec: return join(*v.get_if<graph::UInt64Vec>());
    case ValueType::kVec2f: return join(*v.get_if<graph::Vec2f>());
    case ValueType::kVec3f: return join(*v.get_if<graph::Vec3f>());
    case ValueType::kVec4f: return join(*v.get_if<graph::Vec4f>());
    case ValueType::kVec6f: return join(*v.get_if<graph::Vec6f>());
    case ValueType::kMat4d: return join(v.get_if<graph::Mat4d>()->m);
  }
  return "";
}

std::string in_quotes(std::string_view s, std::size_t max) {
  if (s.size() <= max) return "'" + std::string(s) + "'";
  return "'" + std::string(s.substr(0, max)) + "…' (" + std::to_string(s.size()) + " bytes)";
}

}  // namespace quiver::interop::internal
