#pragma once
// ECDSA P-256 signing with its costly step done ahead: the nonce k, its inverse and r = x(k·G) are
// computed by prepare() (after a delta went out, off its path), and sign() then costs a SHA-256 and
// two modular multiplications (about 2 µs against about 20 µs for the whole signature here).
// A prepared nonce is used for one signature only and then forgotten.

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

struct evp_pkey_st;

namespace quiver::agents::inline replica::security::internal {

class SignAhead {
 public:
  /// @throws std::runtime_error when `key` is not an EC key OpenSSL can sign with.
  explicit SignAhead(evp_pkey_st* key);
  ~SignAhead();
  SignAhead(const SignAhead&) = delete;
  SignAhead& operator=(const SignAhead&) = delete;
  /// Computes a nonce for the next signature unless one is ready. Thread-safe.
  void prepare();
  /// An ECDSA / SHA-256 signature of `data`, DER, with the prepared nonce (or one computed now).
  /// Thread-safe. @throws std::runtime_error when OpenSSL fails.
  std::vector<std::uint8_t> sign(std::span<const std::uint8_t> data);

 private:
  struct Nonce;
  std::unique_ptr<Nonce> take();
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace quiver::agents::inline replica::security::internal
