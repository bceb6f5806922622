#pragma once
/// @file
/// Typed attribute values: a superset of CORTEX DSR's 14 types.
///
/// Threading: Value is a plain value type with no shared state (like std::variant): const
/// members may run concurrently on one object, anything else needs exclusive access. Nothing here
/// throws on purpose; failures are values (as<T>(), decode()).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "quiver/base/hash.h"
#include "quiver/base/result.h"
#include "quiver/base/byte_codec.h"

namespace quiver::graph {

enum class ValueType : std::uint8_t {
  kString = 1,
  kBool,
  kInt32,
  kInt64,
  kUInt32,
  kUInt64,
  kFloat,
  kDouble,
  kBytes,
  kFloatVec,
  kDoubleVec,
  kUInt64Vec,
  kVec2f,
  kVec3f,
  kVec4f,
  kVec6f,
  kMat4d,
};
inline constexpr int kValueTypeCount = 17;

/// Stable name of a type ("double", "vec3f", ...), as used in world files and errors.
/// @returns a static string; "unknown" for a value outside the enum.
const char* to_string(ValueType t);
/// Inverse of to_string; nullopt for an unknown name.
/// @returns the type whose to_string() equals `name` exactly (case-sensitive).
std::optional<ValueType> value_type_from_string(std::string_view name);

using Bytes = std::vector<std::uint8_t>;
using FloatVec = std::vector<float>;
using DoubleVec = std::vector<double>;
using UInt64Vec = std::vector<std::uint64_t>;
using Vec2f = std::array<float, 2>;
using Vec3f = std::array<float, 3>;
using Vec4f = std::array<float, 4>;
using Vec6f = std::array<float, 6>;
/// A 4x4 matrix of doubles, row-major.
struct Mat4d {
  std::array<double, 16> m{};
  /// @returns the 4x4 identity matrix.
  static Mat4d identity() {
    Mat4d r;
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
    return r;
  }
  friend bool operator==(const Mat4d&, const Mat4d&) = default;
};

/// The ValueType that holds a C++ type T (a compile error for a type no attribute holds).
template <class T>
inline constexpr ValueType value_type_of = [] {
  if constexpr (std::is_same_v<T, std::string>) return ValueType::kString;
  else if constexpr (std::is_same_v<T, bool>) return ValueType::kBool;
  else if constexpr (std::is_same_v<T, std::int32_t>) return ValueType::kInt32;
  else if constexpr (std::is_same_v<T, std::int64_t>) return ValueType::kInt64;
  else if constexpr (std::is_same_v<T, std::uint32_t>) return ValueType::kUInt32;
  else if constexpr (std::is_same_v<T, std::uint64_t>) return ValueType::kUInt64;
  else if constexpr (std::is_same_v<T, float>) return ValueType::kFloat;
  else if constexpr (std::is_same_v<T, double>) return ValueType::kDouble;
  else if constexpr (std::is_same_v<T, Bytes>) return ValueType::kBytes;
  else if constexpr (std::is_same_v<T, FloatVec>) return ValueType::kFloatVec;
  else if constexpr (std::is_same_v<T, DoubleVec>) return ValueType::kDoubleVec;
  else if constexpr (std::is_same_v<T, UInt64Vec>) return ValueType::kUInt64Vec;
  else if constexpr (std::is_same_v<T, Vec2f>) return ValueType::kVec2f;
  else if constexpr (std::is_same_v<T, Vec3f>) return ValueType::kVec3f;
  else if constexpr (std::is_same_v<T, Vec4f>) return ValueType::kVec4f;
  else if constexpr (std::is_same_v<T, Vec6f>) return ValueType::kVec6f;
  else if constexpr (std::is_same_v<T, Mat4d>) return ValueType::kMat4d;
  else static_assert(sizeof(T) == 0, "no attribute type holds this C++ type");
}();

/// One attribute value. Small types are stored inline; a Mat4d lives on the heap so that every
/// register does not pay for 128 bytes.
class Value {
 public:
  /// The empty string (kString).
  Value() : v_(std::string()) {}
  /// A kString value.
  Value(std::string v) : v_(std::move(v)) {}          // NOLINT(google-explicit-constructor)
  /// A kString value. @pre `v` is a NUL-terminated string, not nullptr.
  Value(const char* v) : v_(std::string(v)) {}        // NOLINT
  /// A kString value (a copy of `v`).
  Value(std::string_view v) : v_(std::string(v)) {}   // NOLINT
  /// A kBool value.
  Value(bool v) : v_(v) {}                            // NOLINT
  /// Any signed integer is stored as int64 and any unsigned one as uint64, so that `Value(4)`
  /// or `tx.set(n, "count", 4)` never makes an int32 by accident (an int literal is an int).
  /// The 32-bit types are chosen explicitly: Value::int32(), Value::uint32().
  template <class I>
    requires(std::is_integral_v<I> && !std::is_same_v<I, bool>)
  Value(I v)  // NOLINT(google-explicit-constructor)
      : v_(std::in_place_type<std::conditional_t<std::is_signed_v<I>, std::int64_t, std::uint64_t>>, v) {}
  /// @returns an int32 value (DSR's `int` attributes; world files' "int32").
  static Value int32(std::int32_t v) { return Value(std::in_place_type<std::int32_t>, v); }
  /// @returns a uint32 value (DSR's `uint` attributes; world files' "uint32").
  static Value uint32(std::uint32_t v) { return Value(std::in_place_type<std::uint32_t>, v); }
  /// A kFloat value.
  Value(float v) : v_(v) {}                           // NOLINT
  /// A kDouble value.
  Value(double v) : v_(v) {}                          // NOLINT
  /// A kBytes value.
  Value(Bytes v) : v_(std::move(v)) {}                // NOLINT
  /// A kFloatVec value.
  Value(FloatVec v) : v_(std::move(v)) {}             // NOLINT
  /// A kDoubleVec value.
  Value(DoubleVec v) : v_(std::move(v)) {}            // NOLINT
  /// A kUInt64Vec value.
  Value(UInt64Vec v) : v_(std::move(v)) {}            // NOLINT
  /// A kVec2f value.
  Value(Vec2f v) : v_(v) {}                           // NOLINT
  /// A kVec3f value.
  Value(Vec3f v) : v_(v) {}                           // NOLINT
  /// A kVec4f value.
  Value(Vec4f v) : v_(v) {}                           // NOLINT
  /// A kVec6f value.
  Value(Vec6f v) : v_(v) {}                           // NOLINT
  /// A kMat4d value (stored on the heap).
  Value(const Mat4d& v) : v_(Boxed(v)) {}             // NOLINT

  /// @returns the type of the payload.
  ValueType type() const { return static_cast<ValueType>(v_.index() + 1); }

  /// Pointer to the payload if it has type T, else nullptr.
  /// @returns a pointer valid while this Value lives unchanged.
  template <class T>
  const T* get_if() const {
    if constexpr (std::is_same_v<T, Mat4d>) {
      const Boxed* b = std::get_if<Boxed>(&v_);
      return b ? b->p.get() : nullptr;
    } else {
      return std::get_if<T>(&v_);
    }
  }
  /// The payload as T.
  /// @returns a copy of the payload, or kTypeMismatch naming both types
  ///          ("as<int64>(): the value is a string, not an int64"); no conversion is tried.
  template <class T>
  Result<T> as() const {
    if (const T* p = get_if<T>()) return *p;
    return make_error(ErrorCode::kTypeMismatch, std::string("as<") + type_name<T>() + ">(): the value is " +
                                                    article(type()) + ", not " + article(value_type_of<T>));
  }
  /// Stable name of the attribute type that holds T ("int64", "vec3f", ...).
  /// @returns a static string.
  template <class T>
  static const char* type_name() {
    return graph::to_string(value_type_of<T>);
  }
  /// "a string", "an int64": a type name with its article, for error messages.
  /// @returns the article and to_string(t).
  static std::string article(ValueType t);

  /// @returns true if both have the same type and payload; floating-point payloads compare
  ///          bitwise (NaN equals the same NaN, 0.0 differs from -0.0), as digests do.
  friend bool operator==(const Value& a, const Value& b);
  /// Feeds type and payload into a hasher (equal values feed equal bytes).
  void hash_into(Hasher& h) const;
  /// Short human-readable rendering (vectors abbreviated).
  /// @returns e.g. "\"red\"", "4", "[1,2,3]", "<12 bytes>", "<mat4d>".
  std::string to_string() const;
  /// Encoded size estimate in bytes (for limits and statistics).
  /// @returns a string's or byte array's length, a vector's elements times their size, the size
  ///          of a fixed-size type (128 for a Mat4d).
  std::size_t payload_bytes() const;

  /// Binary codec: a type tag byte, then the payload. Appends to `w`; decode() reads it back to
  /// an equal value.
  void encode(bytes::Writer& w) const;
  /// Decodes a value; on failure the reader records why.
  /// @returns the value; on failure (r.ok() false afterwards: kTruncated, kTooLarge past
  ///          `max_value_bytes`, kMalformed for an unknown tag or out-of-range payload) a value
  ///          to be discarded (the empty string if `r` had already failed).
  static Value decode(bytes::Reader& r, std::uint64_t max_value_bytes);

 private:
  template <class T>
  Value(std::in_place_type_t<T> t, T v) : v_(t, v) {}
  struct Boxed {
    std::unique_ptr<Mat4d> p;
    explicit Boxed(const Mat4d& m) : p(std::make_unique<Mat4d>(m)) {}
    Boxed(const Boxed& o) : p(std::make_unique<Mat4d>(*o.p)) {}
    Boxed(Boxed&&) noexcept = default;
    Boxed& operator=(const Boxed& o) {
      p = std::make_unique<Mat4d>(*o.p);
      return *this;
    }
    Boxed& operator=(Boxed&&) noexcept = default;
    friend bool operator==(const Boxed& a, const Boxed& b) { return *a.p == *b.p; }
  };
  std::variant<std::string, bool, std::int32_t, std::int64_t, std::uint32_t, std::uint64_t, float,
               double, Bytes, FloatVec, DoubleVec, UInt64Vec, Vec2f, Vec3f, Vec4f, Vec6f, Boxed>
      v_;
};

}  // namespace quiver::graph
