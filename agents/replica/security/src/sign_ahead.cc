// ECDSA signatures whose nonce was computed ahead of time (sign_ahead.h). OpenSSL 3.0 offers the two
// steps apart only in its EC_KEY interface (ECDSA_sign_setup, ECDSA_do_sign_ex), which it marks
// deprecated but ships: the warnings are silenced here only.
#include "sign_ahead.h"

#include <openssl/bn.h>
#include <openssl/ec.h>
#include <openssl/ecdsa.h>
#include <openssl/evp.h>
#include <openssl/sha.h>

#include <stdexcept>
#include <string>

#include "openssl_util.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"

namespace quiver::agents::inline replica::security::internal {

struct SignAhead::Nonce {
  BIGNUM* kinv = nullptr;
  BIGNUM* r = nullptr;
  ~Nonce() {
    BN_clear_free(kinv);
    BN_clear_free(r);
  }
};

struct SignAhead::State {
  EC_KEY* key = nullptr;
  std::mutex mu;
  std::unique_ptr<Nonce> ready;
  ~State() { EC_KEY_free(key); }
};

namespace {
[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error(ssl_error(ErrorCode::kInternal, "SignAhead: " + what).message);
}
}  // namespace

SignAhead::SignAhead(evp_pkey_st* key) : s_(std::make_unique<State>()) {
  s_->key = EVP_PKEY_get1_EC_KEY(key);
  if (s_->key == nullptr) fail("EVP_PKEY_get1_EC_KEY");
}

SignAhead::~SignAhead() = default;

void SignAhead::prepare() {
  {
    std::lock_guard<std::mutex> lock(s_->mu);
    if (s_->ready) return;
  }
  auto n = std::make_unique<Nonce>();
  if (ECDSA_sign_setup(s_->key, nullptr, &n->kinv, &n->r) != 1) fail("ECDSA_sign_setup");
  std::lock_guard<std::mutex> lock(s_->mu);
  if (!s_->ready) s_->ready = std::move(n);
}

std::unique_ptr<SignAhead::Nonce> SignAhead::take() {
  std::lock_guard<std::mutex> lock(s_->mu);
  return std::move(s_->ready);  // used once: the slot is empty from now on
}

std::vector<std::uint8_t> SignAhead::sign(std::span<const std::uint8_t> data) {
  unsigned char digest[SHA256_DIGEST_LENGTH];
  SHA256(data.data(), data.size(), digest);
  std::unique_ptr<Nonce> n = take();
  ECDSA_SIG* sig = n ? ECDSA_do_sign_ex(digest, sizeof digest, n->kinv, n->r, s_->key)
                     : ECDSA_do_sign(digest, sizeof digest, s_->key);
  if (sig == nullptr) fail("ECDSA_do_sign");
  std::vector<std::uint8_t> out(static_cast<std::size_t>(ECDSA_size(s_->key)));
  unsigned char* p = out.data();
  const int len = i2d_ECDSA_SIG(sig, &p);
  ECDSA_SIG_free(sig);
  if (len <= 0) fail("i2d_ECDSA_SIG");
  out.resize(static_cast<std::size_t>(len));
  return out;
}

}  // namespace quiver::agents::inline replica::security::internal

#pragma GCC diagnostic pop
