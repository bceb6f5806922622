#pragma once
/// @file
/// Little-endian, varint-based byte encoding shared by every Quiver codec. The reader is
/// bounds-checked: every read names the field it was reading, and the first failure sticks, so a
/// decoder can read a whole structure and check once. Lengths are validated against what remains
/// before anything is allocated.

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::inline base::bytes {

/// Appends encoded values to a byte vector it does not own.
class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}

  void u8(std::uint8_t v) { out_.push_back(v); }
  void varint(std::uint64_t v) {
    while (v >= 0x80) {
      out_.push_back(static_cast<std::uint8_t>(v) | 0x80);
      v >>= 7;
    }
    out_.push_back(static_cast<std::uint8_t>(v));
  }
  /// Signed value, zigzag-encoded so small magnitudes stay small.
  void svarint(std::int64_t v) {
    varint((static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63));
  }
  void fixed32(std::uint32_t v) {
    std::uint8_t b[4];
    for (int i = 0; i < 4; ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
    out_.insert(out_.end(), b, b + 4);
  }
  void fixed64(std::uint64_t v) {
    std::uint8_t b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
    out_.insert(out_.end(), b, b + 8);
  }
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    fixed32(bits);
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    fixed64(bits);
  }
  void raw(const void* data, std::size_t n) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    out_.insert(out_.end(), p, p + n);
  }
  /// Length-prefixed bytes.
  void bytes(std::span<const std::uint8_t> b) {
    varint(b.size());
    raw(b.data(), b.size());
  }
  void string(std::string_view s) {
    varint(s.size());
    raw(s.data(), s.size());
  }
  std::size_t size() const { return out_.size(); }
  std::vector<std::uint8_t>& buffer() { return out_; }

 private:
  std::vector<std::uint8_t>& out_;
};

/// Reads from a byte span. After the first failure every read returns a zero value and `ok()`
/// stays false; `error()` tells which field failed at which offset.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> in, std::string_view what) : p_(in.data()), begin_(in.data()),
                                                                     end_(in.data() + in.size()), what_(what) {}

  bool ok() const { return !failed_; }
  bool at_end() const { return p_ == end_; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  std::size_t offset() const { return static_cast<std::size_t>(p_ - begin_); }
  const Error& error() const { return error_; }

  std::uint8_t u8(const char* field) {
    if (failed_) [[unlikely]]
      return 0;
    if (p_ == end_) [[unlikely]] {
      fail(ErrorCode::kTruncated, field, "input ended");
      return 0;
    }
    return *p_++;
  }
  std::uint64_t varint(const char* field) {
    if (failed_) [[unlikely]]
      return 0;
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (p_ == end_) [[unlikely]] {
        fail(ErrorCode::kTruncated, field, "input ended inside a varint");
        return 0;
      }
      std::uint8_t b = *p_++;
      if (shift == 63 && b > 1) [[unlikely]] {
        fail(ErrorCode::kMalformed, field, "varint overflows 64 bits");
        return 0;
      }
      v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    fail(ErrorCode::kMalformed, field, "varint longer than 10 bytes");
    return 0;
  }
  std::int64_t svarint(const char* field) {
    std::uint64_t u = varint(field);
    return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
  }
  /// A varint that must be at most `max` (a count or a length about to be used).
  std::uint64_t bounded(const char* field, std::uint64_t max) {
    std::uint64_t v = varint(field);
    if (failed_) [[unlikely]]
      return 0;
    if (v > max) [[unlikely]] {
      fail(ErrorCode::kTooLarge, field,
           "value " + std::to_string(v) + " exceeds the limit " + std::to_string(max));
      return 0;
    }
    return v;
  }
  /// A count of items each at least `min_item_bytes` long: checked against what remains.
  std::uint64_t count(const char* field, std::uint64_t max, std::size_t min_item_bytes = 1) {
    std::uint64_t v = bounded(field, max);
    if (failed_) [[unlikely]]
      return 0;
    if (min_item_bytes > 0 && v > remaining() / min_item_bytes) [[unlikely]] {
      fail(ErrorCode::kTruncated, field,
           "count " + std::to_string(v) + " needs more bytes than the " +
               std::to_string(remaining()) + " that remain");
      return 0;
    }
    return v;
  }
  std::uint32_t fixed32(const char* field) {
    if (!need(4, field)) return 0;
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p_[i]) << (8 * i);
    p_ += 4;
    return v;
  }
  std::uint64_t fixed64(const char* field) {
    if (!need(8, field)) return 0;
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p_[i]) << (8 * i);
    p_ += 8;
    return v;
  }
  float f32(const char* field) {
    std::uint32_t bits = fixed32(field);
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
  }
  double f64(const char* field) {
    std::uint64_t bits = fixed64(field);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  /// Length-prefixed bytes as a view into the input (valid while the input is).
  std::span<const std::uint8_t> bytes(const char* field, std::uint64_t max) {
    std::uint64_t n = bounded(field, max);
    if (!need(n, field)) return {};
    std::span<const std::uint8_t> out(p_, n);
    p_ += n;
    return out;
  }
  std::string_view string(const char* field, std::uint64_t max) {
    auto b = bytes(field, max);
    return {reinterpret_cast<const char*>(b.data()), b.size()};
  }
  std::span<const std::uint8_t> raw(const char* field, std::size_t n) {
    if (!need(n, field)) return {};
    std::span<const std::uint8_t> out(p_, n);
    p_ += n;
    return out;
  }

  /// Records a semantic failure found by the decoder itself (e.g. an index out of range).
  void fail(ErrorCode code, std::string_view field, std::string_view why) {
    if (failed_) return;
    failed_ = true;
    error_ = Error{code, std::string(what_) + ": " + std::string(why) + " while reading '" +
                             std::string(field) + "' at byte " + std::to_string(offset()) + " of " +
                             std::to_string(end_ - begin_)};
  }

 private:
  bool need(std::uint64_t n, const char* field) {
    if (failed_) return false;
    if (n > remaining()) [[unlikely]] {
      fail(ErrorCode::kTruncated, field,
           "needs " + std::to_string(n) + " bytes but " + std::to_string(remaining()) + " remain");
      return false;
    }
    return true;
  }

  const std::uint8_t* p_;
  const std::uint8_t* begin_;
  const std::uint8_t* end_;
  std::string_view what_;
  Error error_;
  bool failed_ = false;
};

}  // namespace quiver::inline base::bytes
