// Typed attribute values: their type names, equality, hashing, text, and their encoding and bounded decoding.
#include "quiver/graph/value.h"

#include <cstdio>
#include <cstring>

namespace quiver::graph {
namespace {

constexpr const char* kTypeNames[kValueTypeCount] = {
    "string", "bool",       "int32",      "int64", "uint32", "uint64", "float", "double", "bytes",
    "float_vec", "double_vec", "uint64_vec", "vec2f", "vec3f", "vec4f", "vec6f", "mat4d"};

template <class T>
void encode_vec(bytes::Writer& w, const std::vector<T>& v) {
  w.varint(v.size());
  for (const T& x : v) {
    if constexpr (std::is_same_v<T, float>) w.f32(x);
    else if constexpr (std::is_same_v<T, double>) w.f64(x);
    else w.fixed64(x);
  }
}

template <class T>
std::vector<T> decode_vec(bytes::Reader& r, std::uint64_t max_bytes) {
  std::vector<T> out;
  std::uint64_t n = r.count("vector length", max_bytes / sizeof(T), sizeof(T));
  out.reserve(n);
  for (std::uint64_t i = 0; i < n && r.ok(); ++i) {
    if constexpr (std::is_same_v<T, float>) out.push_back(r.f32("vector element"));
    else if constexpr (std::is_same_v<T, double>) out.push_back(r.f64("vector element"));
    else out.push_back(r.fixed64("vector element"));
  }
  return out;
}

template <std::size_t N>
std::array<float, N> decode_arr(bytes::Reader& r) {
  std::array<float, N> a{};
  for (auto& x : a) x = r.f32("array element");
  return a;
}

}  // namespace

const char* to_string(ValueType t) {
  int i = static_cast<int>(t) - 1;
  return (i >= 0 && i < kValueTypeCount) ? kTypeNames[i] : "unknown";
}

std::string Value::article(ValueType t) {
  const char* n = graph::to_string(t);
  const bool vowel = n[0] == 'i' || n[0] == 'u' || n[0] == 'a' || n[0] == 'e' || n[0] == 'o';
  return std::string(vowel ? "an " : "a ") + n;
}

std::optional<ValueType> value_type_from_string(std::string_view name) {
  for (int i = 0; i < kValueTypeCount; ++i)
    if (name == kTypeNames[i]) return static_cast<ValueType>(i + 1);
  return std::nullopt;
}

bool operator==(const Value& a, const Value& b) {
  // Floating-point payloads compare bitwise, so NaN == NaN and equality agrees with digests.
  if (a.v_.index() != b.v_.index()) return false;
  return std::visit(
      [&](const auto& x) -> bool {
        using T = std::decay_t<decltype(x)>;
        const T& y = std::get<T>(b.v_);
        if constexpr (std::is_same_v<T, Value::Boxed>) {
          return std::memcmp(x.p->m.data(), y.p->m.data(), sizeof(double) * 16) == 0;
        } else if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>) {
          return std::memcmp(&x, &y, sizeof(T)) == 0;
        } else if constexpr (std::is_same_v<T, FloatVec> || std::is_same_v<T, DoubleVec>) {
          return x.size() == y.size() &&
                 (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
        } else if constexpr (std::is_same_v<T, Vec2f> || std::is_same_v<T, Vec3f> ||
                             std::is_same_v<T, Vec4f> || std::is_same_v<T, Vec6f>) {
          return std::memcmp(x.data(), y.data(), sizeof(T)) == 0;
        } else {
          return x == y;
        }
      },
      a.v_);
}

void Value::hash_into(Hasher& h) const {
  h.u64(static_cast<std::uint64_t>(type()));
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string>) h.str(x);
        else if constexpr (std::is_same_v<T, bool>) h.u64(x ? 1 : 0);
        else if constexpr (std::is_same_v<T, float>) h.f32(x);
        else if constexpr (std::is_same_v<T, double>) h.f64(x);
        else if constexpr (std::is_integral_v<T>) h.u64(static_cast<std::uint64_t>(x));
        else if constexpr (std::is_same_v<T, Bytes>) h.bytes(x.data(), x.size());
        else if constexpr (std::is_same_v<T, FloatVec>) {
          h.u64(x.size());
          for (float f : x) h.f32(f);
        } else if constexpr (std::is_same_v<T, DoubleVec>) {
          h.u64(x.size());
          for (double f : x) h.f64(f);
        } else if constexpr (std::is_same_v<T, UInt64Vec>) {
          h.u64(x.size());
          for (auto f : x) h.u64(f);
        } else if constexpr (std::is_same_v<T, Boxed>) {
          for (double f : x.p->m) h.f64(f);
        } else {
          for (float f : x) h.f32(f);
        }
      },
      v_);
}

std::size_t Value::payload_bytes() const {
  return std::visit(
      [](const auto& x) -> std::size_t {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, Bytes>) return x.size();
        else if constexpr (std::is_same_v<T, FloatVec>) return x.size() * 4;
        else if constexpr (std::is_same_v<T, DoubleVec> || std::is_same_v<T, UInt64Vec>) return x.size() * 8;
        else if constexpr (std::is_same_v<T, Boxed>) return 128;
        else return sizeof(T);
      },
      v_);
}

std::string Value::to_string() const {
  char buf[64];
  return std::visit(
      [&](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string>) return "\"" + x + "\"";
        else if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
        else if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>) {
          std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(x));
          return buf;
        } else if constexpr (std::is_integral_v<T>) return std::to_string(x);
        else if constexpr (std::is_same_v<T, Bytes>) return "<" + std::to_string(x.size()) + " bytes>";
        else if constexpr (std::is_same_v<T, Boxed>) return "<mat4d>";
        else {
          std::string s = "[";
          std::size_t n = 0;
          for (const auto& e : x) {
            if (n++) s += ",";
            if (n > 8) {
              s += "...(" + std::to_string(x.size()) + ")";
              break;
            }
            std::snprintf(buf, sizeof buf, "%g", static_cast<double>(e));
            s += buf;
          }
          return s + "]";
        }
      },
      v_);
}

void Value::encode(bytes::Writer& w) const {
  w.u8(static_cast<std::uint8_t>(type()));
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string>) w.string(x);
        else if constexpr (std::is_same_v<T, bool>) w.u8(x ? 1 : 0);
        else if constexpr (std::is_same_v<T, std::int32_t> || std::is_same_v<T, std::int64_t>) w.svarint(x);
        else if constexpr (std::is_same_v<T, std::uint32_t> || std::is_same_v<T, std::uint64_t>) w.varint(x);
        else if constexpr (std::is_same_v<T, float>) w.f32(x);
        else if constexpr (std::is_same_v<T, double>) w.f64(x);
        else if constexpr (std::is_same_v<T, Bytes>) w.bytes(x);
        else if constexpr (std::is_same_v<T, FloatVec> || std::is_same_v<T, DoubleVec> ||
                           std::is_same_v<T, UInt64Vec>) encode_vec(w, x);
        else if constexpr (std::is_same_v<T, Boxed>) {
          for (double f : x.p->m) w.f64(f);
        } else {
          for (float f : x) w.f32(f);
        }
      },
      v_);
}

Value Value::decode(bytes::Reader& r, std::uint64_t max_value_bytes) {
  std::uint8_t tag = r.u8("value type");
  if (!r.ok()) return Value();
  switch (static_cast<ValueType>(tag)) {
    case ValueType::kString: return Value(std::string(r.string("string value", max_value_bytes)));
    case ValueType::kBool: {
      std::uint8_t b = r.u8("bool value");
      if (b > 1) r.fail(ErrorCode::kMalformed, "bool value", "a bool must be 0 or 1");
      return Value(b == 1);
    }
    case ValueType::kInt32: {
      std::int64_t v = r.svarint("int32 value");
      if (v < INT32_MIN || v > INT32_MAX) r.fail(ErrorCode::kMalformed, "int32 value", "out of int32 range");
      return Value::int32(static_cast<std::int32_t>(v));
    }
    case ValueType::kInt64: return Value(static_cast<std::int64_t>(r.svarint("int64 value")));
    case ValueType::kUInt32: {
      std::uint64_t v = r.varint("uint32 value");
      if (v > UINT32_MAX) r.fail(ErrorCode::kMalformed, "uint32 value", "out of uint32 range");
      return Value::uint32(static_cast<std::uint32_t>(v));
    }
    case ValueType::kUInt64: return Value(static_cast<std::uint64_t>(r.varint("uint64 value")));
    case ValueType::kFloat: return Value(r.f32("float value"));
    case ValueType::kDouble: return Value(r.f64("double value"));
    case ValueType::kBytes: {
      auto b = r.bytes("bytes value", max_value_bytes);
      return Value(Bytes(b.begin(), b.end()));
    }
    case ValueType::kFloatVec: return Value(decode_vec<float>(r, max_value_bytes));
    case ValueType::kDoubleVec: return Value(decode_vec<double>(r, max_value_bytes));
    case ValueType::kUInt64Vec: return Value(decode_vec<std::uint64_t>(r, max_value_bytes));
    case ValueType::kVec2f: return Value(decode_arr<2>(r));
    case ValueType::kVec3f: return Value(decode_arr<3>(r));
    case ValueType::kVec4f: return Value(decode_arr<4>(r));
    case ValueType::kVec6f: return Value(decode_arr<6>(r));
    case ValueType::kMat4d: {
      Mat4d m;
      for (double& x : m.m) x = r.f64("mat4d element");
      return Value(m);
    }
  }
  r.fail(ErrorCode::kMalformed, "value type", "unknown value type tag " + std::to_string(tag));
  return Value();
}

}  // namespace quiver::graph
