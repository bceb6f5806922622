// World files' attribute values: typed JSON read with checks (numbers in range, base64 bytes,
// fixed-size vectors, matrices) and written back.

#include <cmath>
#include <limits>

#include "quiver/graph/limits.h"
#include "quiver/graph/world_file.h"
#include "world_values.h"

namespace quiver::graph {
namespace {

using internal::Failure;
using internal::json;

constexpr char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64_encode(const Bytes& b) {
  std::string out;
  out.reserve((b.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < b.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint32_t>(b[i]) << 16;
    if (i + 1 < b.size()) v |= static_cast<std::uint32_t>(b[i + 1]) << 8;
    if (i + 2 < b.size()) v |= b[i + 2];
    out += kB64[(v >> 18) & 63];
    out += kB64[(v >> 12) & 63];
    out += i + 1 < b.size() ? kB64[(v >> 6) & 63] : '=';
    out += i + 2 < b.size() ? kB64[v & 63] : '=';
  }
  return out;
}

bool base64_decode(std::string_view s, Bytes& out) {
  if (s.size() % 4 != 0) return false;
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  out.clear();
  for (std::size_t i = 0; i < s.size(); i += 4) {
    int a = val(s[i]), b = val(s[i + 1]);
    int c = s[i + 2] == '=' ? 0 : val(s[i + 2]);
    int d = s[i + 3] == '=' ? 0 : val(s[i + 3]);
    if (a < 0 || b < 0 || c < 0 || d < 0) return false;
    if (s[i + 2] == '=' && s[i + 3] != '=') return false;
    if ((s[i + 2] == '=' || s[i + 3] == '=') && i + 4 != s.size()) return false;
    std::uint32_t v = (a << 18) | (b << 12) | (c << 6) | d;
    out.push_back(static_cast<std::uint8_t>(v >> 16));
    if (s[i + 2] != '=') out.push_back(static_cast<std::uint8_t>(v >> 8));
    if (s[i + 3] != '=') out.push_back(static_cast<std::uint8_t>(v));
  }
  return true;
}

template <class T>
bool number_as(const json& j, T& out) {
  if constexpr (std::is_floating_point_v<T>) {
    if (!j.is_number()) return false;
    double d = j.get<double>();
    if constexpr (std::is_same_v<T, float>) {
      if (std::isfinite(d) && std::fabs(d) > std::numeric_limits<float>::max()) return false;
    }
    out = static_cast<T>(d);
    return true;
  } else if constexpr (std::is_signed_v<T>) {
    if (j.is_number_unsigned()) {
      auto v = j.get<std::uint64_t>();
      if (v > static_cast<std::uint64_t>(std::numeric_limits<T>::max())) return false;
      out = static_cast<T>(v);
      return true;
    }
    if (!j.is_number_integer()) return false;
    auto v = j.get<std::int64_t>();
    if (v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max()) return false;
    out = static_cast<T>(v);
    return true;
  } else {
    if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<std::int64_t>() >= 0)) return false;
    auto v = j.get<std::uint64_t>();
    if (v > std::numeric_limits<T>::max()) return false;
    out = static_cast<T>(v);
    return true;
  }
}

template <class T>
bool array_as(const json& j, std::vector<T>& out) {
  if (!j.is_array()) return false;
  out.clear();
  out.reserve(j.size());
  for (const json& e : j) {
    T v{};
    if (!number_as(e, v)) return false;
    out.push_back(v);
  }
  return true;
}

template <std::size_t N>
bool fixed_as(const json& j, std::array<float, N>& out) {
  if (!j.is_array() || j.size() != N) return false;
  for (std::size_t i = 0; i < N; ++i)
    if (!number_as(j[i], out[i])) return false;
  return true;
}

}  // namespace

namespace internal {

bool parse_value(const json& j, const std::string& where, Value& out, Failure& f) {
  auto bad = [&](const std::string& what) {
    f = Failure{where, what};
    return false;
  };
  if (j.is_string()) return out = Value(j.get<std::string>()), true;
  if (j.is_boolean()) return out = Value(j.get<bool>()), true;
  if (j.is_number_unsigned()) {
    auto v = j.get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(INT64_MAX)) return out = Value(v), true;
    return out = Value(static_cast<std::int64_t>(v)), true;
  }
  if (j.is_number_integer()) return out = Value(j.get<std::int64_t>()), true;
  if (j.is_number_float()) return out = Value(j.get<double>()), true;
  if (!j.is_object() || j.size() != 1)
    return bad("expected a string, bool, number or an object {\"<type>\": value} with one key");
  const std::string& tname = j.begin().key();
  const json& v = j.begin().value();
  auto type = value_type_from_string(tname);
  if (!type) return bad("unknown value type '" + tname + "'");
  std::string expect = std::string("a value of type ") + tname;
  switch (*type) {
    case ValueType::kString: {
      if (v.is_string()) return out = Value(v.get<std::string>()), true;
      // Text that is not UTF-8 is written as {"string": {"base64": "..."}} (JSON holds only UTF-8).
      Bytes b;
      auto b64 = v.is_object() && v.size() == 1 ? v.find("base64") : v.end();
      if (b64 == v.end() || !b64->is_string() || !base64_decode(b64->get<std::string>(), b))
        return bad("expected a string, or {\"base64\": ...} for text that is not UTF-8");
      return out = Value(std::string(b.begin(), b.end())), true;
    }
    case ValueType::kBool:
      if (!v.is_boolean()) return bad("expected " + expect);
      return out = Value(v.get<bool>()), true;
    case ValueType::kInt32: {
      std::int32_t x;
      if (!number_as(v, x)) return bad("expected an integer in int32 range");
      return out = Value::int32(x), true;
    }
    case ValueType::kInt64: {
      std::int64_t x;
      if (!number_as(v, x)) return bad("expected an integer in int64 range");
      return out = Value(x), true;
    }
    case ValueType::kUInt32: {
      std::uint32_t x;
      if (!number_as(v, x)) return bad("expected an integer in uint32 range");
      return out = Value::uint32(x), true;
    }
    case ValueType::kUInt64: {
      std::uint64_t x;
      if (!number_as(v, x)) return bad("expected an integer in uint64 range");
      return out = Value(x), true;
    }
    case ValueType::kFloat: {
      float x;
      if (!number_as(v, x)) return bad("expected a number in float range");
      return out = Value(x), true;
    }
    case ValueType::kDouble: {
      double x;
      if (!number_as(v, x)) return bad("expected a number");
      return out = Value(x), true;
    }
    case ValueType::kBytes: {
      Bytes b;
      if (!v.is_string() || !base64_decode(v.get<std::string>(), b)) return bad("expected base64 text");
      return out = Value(std::move(b)), true;
    }
    case ValueType::kFloatVec: {
      FloatVec x;
      if (!array_as(v, x)) return bad("expected an array of numbers");
      return out = Value(std::move(x)), true;
    }
    case ValueType::kDoubleVec: {
      DoubleVec x;
      if (!array_as(v, x)) return bad("expected an array of numbers");
      return out = Value(std::move(x)), true;
    }
    case ValueType::kUInt64Vec: {
      UInt64Vec x;
      if (!array_as(v, x)) return bad("expected an array of unsigned integers");
      return out = Value(std::move(x)), true;
    }
    case ValueType::kVec2f: {
      Vec2f x;
      if (!fixed_as(v, x)) return bad("expected an array of 2 numbers");
      return out = Value(x), true;
    }
    case ValueType::kVec3f: {
      Vec3f x;
      if (!fixed_as(v, x)) return bad("expected an array of 3 numbers");
      return out = Value(x), true;
    }
    case ValueType::kVec4f: {
      Vec4f x;
      if (!fixed_as(v, x)) return bad("expected an array of 4 numbers");
      return out = Value(x), true;
    }
    case ValueType::kVec6f: {
      Vec6f x;
      if (!fixed_as(v, x)) return bad("expected an array of 6 numbers");
      return out = Value(x), true;
    }
    case ValueType::kMat4d: {
      Mat4d m;
      if (!v.is_array() || v.size() != 16) return bad("expected an array of 16 numbers (row-major 4x4)");
      for (std::size_t i = 0; i < 16; ++i)
        if (!number_as(v[i], m.m[i])) return bad("expected an array of 16 numbers (row-major 4x4)");
      return out = Value(m), true;
    }
  }
  return bad("unsupported value type");
}

json value_to_json(const Value& v) {
  auto typed = [&](const char* t, json x) {
    json o = json::object();
    o[t] = std::move(x);
    return o;
  };
  switch (v.type()) {
    case ValueType::kString: {
      const std::string& t = *v.get_if<std::string>();
      if (valid_utf8(t)) return t;
      json b64 = json::object();
      b64["base64"] = base64_encode(Bytes(t.begin(), t.end()));
      return typed("string", std::move(b64));
    }
    case ValueType::kBool: return *v.get_if<bool>();
    case ValueType::kInt64: return *v.get_if<std::int64_t>();
    case ValueType::kDouble: {
      double d = *v.get_if<double>();
      if (!std::isfinite(d)) return typed("double", nullptr);
      // A double that happens to be integral must stay a double on reload.
      if (d == std::floor(d) && std::fabs(d) < 1e15) return typed("double", d);
      return d;
    }
    case ValueType::kInt32: return typed("int32", *v.get_if<std::int32_t>());
    case ValueType::kUInt32: return typed("uint32", *v.get_if<std::uint32_t>());
    case ValueType::kUInt64: return typed("uint64", *v.get_if<std::uint64_t>());
    case ValueType::kFloat: return typed("float", *v.get_if<float>());
    case ValueType::kBytes: return typed("bytes", base64_encode(*v.get_if<Bytes>()));
    case ValueType::kFloatVec: return typed("float_vec", *v.get_if<FloatVec>());
    case ValueType::kDoubleVec: return typed("double_vec", *v.get_if<DoubleVec>());
    case ValueType::kUInt64Vec: return typed("uint64_vec", *v.get_if<UInt64Vec>());
    case ValueType::kVec2f: return typed("vec2f", *v.get_if<Vec2f>());
    case ValueType::kVec3f: return typed("vec3f", *v.get_if<Vec3f>());
    case ValueType::kVec4f: return typed("vec4f", *v.get_if<Vec4f>());
    case ValueType::kVec6f: return typed("vec6f", *v.get_if<Vec6f>());
    case ValueType::kMat4d: return typed("mat4d", v.get_if<Mat4d>()->m);
  }
  return nullptr;
}

}  // namespace internal

using internal::Failure;
using internal::json;
using internal::parse_value;
using internal::value_to_json;

Result<Value> value_from_json_text(std::string_view text, std::string_view where) {
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return make_error(ErrorCode::kMalformed, std::string(where) + ": not valid JSON");
  Value v;
  Failure f;
  if (!parse_value(j, std::string(where), v, f)) return make_error(ErrorCode::kMalformed, f.where + ": " + f.what);
  return v;
}

std::string value_to_json_text(const Value& v) { return value_to_json(v).dump(); }

}  // namespace quiver::graph
