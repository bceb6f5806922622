#pragma once
/// @file
/// Expected failures as values: `quiver::Error` carries a code from one catalogue and a message
/// that names what was wrong and where; `Result<T>` holds either a value or an Error.
///
/// Threading: plain values. Reading the wrong alternative of a Result is a bug: the accessors
/// then throw std::bad_variant_access (the only throws here).

#include <cstdint>
#include <string>
#include <utility>
#include <variant>

namespace quiver::inline base {

/// One catalogue of error codes. A new code is added only when a caller would react differently.
enum class ErrorCode : std::uint16_t {
  kInvalidArgument = 1,  ///< The caller passed a value the function cannot accept.
  kNotFound,             ///< A node, edge, attribute, frame or file does not exist.
  kAlreadyExists,        ///< A unique name or key is taken.
  kMalformed,            ///< Input bytes or text do not follow the format.
  kTruncated,            ///< Input ended before the format said it would.
  kTooLarge,             ///< A length or count exceeds the configured limit.
  kUnsupportedVersion,   ///< A format version this build does not understand.
  kTypeMismatch,         ///< A typed read found a value of another type.
  kRefused,              ///< A rule, grammar or lock refused the change.
  kTimeout,              ///< A bounded wait ended before its condition held.
  kIo,                   ///< The operating system reported a failure.
  kNotConnected,         ///< Two frames are in separate trees.
  kExtrapolation,        ///< A timed lookup asked outside the stored history.
  kTransport,            ///< The network layer failed.
  kEquivocation,         ///< A peer sent two different things under one name (a forgery or a bug).
  kInternal,             ///< A bug: an invariant of Quiver itself did not hold.
  kPermissionDenied,     ///< The change's author may not make it, or is not who it claims (docs/security.md).
};

/// Stable lowercase name of an error code ("not_found", ...). Thread-safe.
/// @returns a static string; "unknown" for a value outside the catalogue.
const char* to_string(ErrorCode code);

/// An error value: a code and a human-readable message naming the culprit.
struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string message;

  /// @returns "<code>: <message>", e.g. "not_found: node 'mug' does not exist".
  std::string to_string() const;
};

/// @returns Error{code, message}.
inline Error make_error(ErrorCode code, std::string message) { return Error{code, std::move(message)}; }

/// Either a T or an Error. Cheap to move; `ok()` tells which; `value()` on an error is a bug.
template <class T>
class [[nodiscard]] Result {
 public:
  /// A success holding `value`.
  Result(T value) : v_(std::move(value)) {}                 // NOLINT(google-explicit-constructor)
  /// A failure holding `error`.
  Result(Error error) : v_(std::move(error)) {}             // NOLINT(google-explicit-constructor)
  /// @returns true if this holds a value.
  bool ok() const { return v_.index() == 0; }
  /// @returns ok().
  explicit operator bool() const { return ok(); }
  /// @returns the value. @pre ok(). @throws std::bad_variant_access if not.
  T& value() & { return std::get<0>(v_); }
  /// @returns the value. @pre ok(). @throws std::bad_variant_access if not.
  const T& value() const& { return std::get<0>(v_); }
  /// @returns the value, moved out. @pre ok(). @throws std::bad_variant_access if not.
  T&& value() && { return std::get<0>(std::move(v_)); }
  /// @returns a pointer to the value. @pre ok(). @throws std::bad_variant_access if not.
  T* operator->() { return &std::get<0>(v_); }
  /// @returns a pointer to the value. @pre ok(). @throws std::bad_variant_access if not.
  const T* operator->() const { return &std::get<0>(v_); }
  /// @returns the value. @pre ok(). @throws std::bad_variant_access if not.
  T& operator*() & { return std::get<0>(v_); }
  /// @returns the value. @pre ok(). @throws std::bad_variant_access if not.
  const T& operator*() const& { return std::get<0>(v_); }
  /// @returns the error. @pre !ok(). @throws std::bad_variant_access if not.
  const Error& error() const { return std::get<1>(v_); }
  /// @returns a copy of the value, or `fallback` on an error.
  T value_or(T fallback) const { return ok() ? std::get<0>(v_) : std::move(fallback); }

 private:
  std::variant<T, Error> v_;
};

/// Success or an Error, for operations with no value.
class [[nodiscard]] Status {
 public:
  Status() = default;
  /// A failure holding `error`.
  Status(Error error) : error_(std::move(error)), failed_(true) {}  // NOLINT
  /// @returns a success (as Status{}).
  static Status Ok() { return Status(); }
  /// @returns true on success.
  bool ok() const { return !failed_; }
  /// @returns ok().
  explicit operator bool() const { return ok(); }
  /// @returns the error; on success a default Error (kInternal, empty message), not a real one.
  const Error& error() const { return error_; }

 private:
  Error error_;
  bool failed_ = false;
};

}  // namespace quiver
