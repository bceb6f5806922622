#pragma once
/// @file
/// Little-endian, varint-based byte encoding shared by every Quiver codec. The reader is
/// bounds-checked: every read names the field it was reading, and the first failure sticks, so a
/// decoder can read a whole structure and check once. Lengths are validated against what remains
/// before anything is allocated.
///
/// Threading: a Writer or Reader is used by one thread at a time. Failures are values recorded in
/// the Reader; nothing here throws (but std::bad_alloc from a Writer's vector).

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
  /// Appends to `out`. @pre `out` outlives the writer.
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}

  /// Appends one byte.
  void u8(std::uint8_t v) { out_.push_back(v); }
  /// Appends `v` as an LEB128 varint (1 to 10 bytes).
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
  /// Appends `v` as 4 bytes, little-endian.
  void fixed32(std::uint32_t v) {
    std::uint8_t b[4];
    for (int i = 0; i < 4; ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
    out_.insert(out_.end(), b, b + 4);
  }
  /// Appends `v` as 8 bytes, little-endian.
  void fixed64(std::uint64_t v) {
    std::uint8_t b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
    out_.insert(out_.end(), b, b + 8);
  }
  /// Appends the IEEE-754 bits of `v` as fixed32 (NaN payloads kept).
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    fixed32(bits);
  }
  /// Appends the IEEE-754 bits of `v` as fixed64 (NaN payloads kept).
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    fixed64(bits);
  }
  /// Appends `n` bytes as they are, no length prefix. @pre `data` points to `n` readable bytes.
  void raw(const void* data, std::size_t n) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    out_.insert(out_.end(), p, p + n);
  }
  /// Length-prefixed bytes.
  void bytes(std::span<const std::uint8_t> b) {
    varint(b.size());
    raw(b.data(), b.size());
  }
  /// Length-prefixed text, as bytes() (no encoding check).
  void string(std::string_view s) {
    varint(s.size());
    raw(s.data(), s.size());
  }
  /// @returns the size of the whole output vector (including what it held before this writer).
  std::size_t size() const { return out_.size(); }
  /// @returns the output vector.
  std::vector<std::uint8_t>& buffer() { return out_; }

 private:
  std::vector<std::uint8_t>& out_;
};

/// Reads from a byte span. After the first failure every read returns a zero value and `ok()`
/// stays false; `error()` tells which field failed at which offset.
class Reader {
 public:
  /// Reads `in`; `what` names the input in errors ("graph delta").
  /// @pre `in`'s bytes and `what`'s text outlive the reader (and the views it returns).
  Reader(std::span<const std::uint8_t> in, std::string_view what) : p_(in.data()), begin_(in.data()),
                                                                     end_(in.data() + in.size()), what_(what) {}

  /// @returns false once any read or fail() has failed.
  bool ok() const { return !failed_; }
  /// @returns true if every byte has been read.
  bool at_end() const { return p_ == end_; }
  /// @returns the number of bytes not read yet.
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  /// @returns the number of bytes read so far.
  std::size_t offset() const { return static_cast<std::size_t>(p_ - begin_); }
  /// @returns the first failure (code, field, offset); meaningful only when !ok().
  const Error& error() const { return error_; }

  // Every read below: `field` (a NUL-terminated string) names the field in a failure. After a
  // failure (this one or an earlier one) it returns zero / an empty view and reads nothing.

  /// @returns the next byte; kTruncated at the end.
  std::uint8_t u8(const char* field) {
    if (failed_) [[unlikely]]
      return 0;
    if (p_ == end_) [[unlikely]] {
      fail(ErrorCode::kTruncated, field, "input ended");
      return 0;
    }
    return *p_++;
  }
  /// @returns the next LEB128 varint; kTruncated if the input ends inside it, kMalformed if it
  ///          overflows 64 bits.
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
  /// @returns the next zigzag varint (Writer::svarint()); failures as varint().
  std::int64_t svarint(const char* field) {
    std::uint64_t u = varint(field);
    return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
  }
  /// A varint that must be at most `max` (a count or a length about to be used).
  /// @returns the value; kTooLarge above `max`, or varint()'s failures.
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
  /// @returns the count; kTooLarge above `max`, kTruncated if the items cannot fit in what
  ///          remains, or varint()'s failures.
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
  /// @returns the next 4 bytes, little-endian; kTruncated if fewer remain.
  std::uint32_t fixed32(const char* field) {
    if (!need(4, field)) return 0;
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p_[i]) << (8 * i);
    p_ += 4;
    return v;
  }
  /// @returns the next 8 bytes, little-endian; kTruncated if fewer remain.
  std::uint64_t fixed64(const char* field) {
    if (!need(8, field)) return 0;
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p_[i]) << (8 * i);
    p_ += 8;
    return v;
  }
  /// @returns the float whose bits fixed32() reads (any bit pattern, NaN included).
  float f32(const char* field) {
    std::uint32_t bits = fixed32(field);
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
  }
  /// @returns the double whose bits fixed64() reads (any bit pattern, NaN included).
  double f64(const char* field) {
    std::uint64_t bits = fixed64(field);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  /// Length-prefixed bytes as a view into the input (valid while the input is).
  /// @returns the view; kTooLarge if the length exceeds `max`, kTruncated if fewer remain.
  std::span<const std::uint8_t> bytes(const char* field, std::uint64_t max) {
    std::uint64_t n = bounded(field, max);
    if (!need(n, field)) return {};
    std::span<const std::uint8_t> out(p_, n);
    p_ += n;
    return out;
  }
  /// @returns length-prefixed text as a view into the input, as bytes() (no UTF-8 check).
  std::string_view string(const char* field, std::uint64_t max) {
    auto b = bytes(field, max);
    return {reinterpret_cast<const char*>(b.data()), b.size()};
  }
  /// @returns the next `n` bytes as a view into the input; kTruncated if fewer remain.
  std::span<const std::uint8_t> raw(const char* field, std::size_t n) {
    if (!need(n, field)) return {};
    std::span<const std::uint8_t> out(p_, n);
    p_ += n;
    return out;
  }

  /// Records a semantic failure found by the decoder itself (e.g. an index out of range).
  /// Only the first failure is kept: after one, this does nothing.
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
