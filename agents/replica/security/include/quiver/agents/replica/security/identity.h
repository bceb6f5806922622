#pragma once
/// @file
/// Graph-level identity: an agent signs payloads with the private key of its DDS Security
/// identity (keys.h), and its peers verify them against the certificates in the same directory.
/// An agent id is quiver::fnv1a64 of the agent's name, the CN of its certificate.
///
/// ECDSA P-256 over SHA-256; signatures are DER, at most 72 bytes (docs/security.md gives the
/// measured cost of sign and verify).
///
/// Threading: both classes are meant for one owner thread; sign(), prepare() and verify() are
/// const, and concurrent calls are safe too (the one prepared nonce is taken under a lock; verify()
/// uses a fresh OpenSSL context per call). reload() must not run concurrently with anything else on the same IdentityBook.

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "quiver/base/result.h"

struct evp_pkey_st;  // OpenSSL's EVP_PKEY

namespace quiver::agents::inline replica::security {

namespace internal {
class SignAhead;
struct KeyDeleter {
  void operator()(evp_pkey_st* key) const;
};
using KeyPtr = std::unique_ptr<evp_pkey_st, KeyDeleter>;
}  // namespace internal

/// The agent's private identity key (DIR/agents/NAME/key.pem): signs payloads.
class Signer {
 public:
  /// @returns kNotFound when DIR/agents/NAME/key.pem is missing, kMalformed when it holds no
  /// P-256 key, kInvalidArgument for a bad name.
  static Result<Signer> load(const std::string& dir, const std::string& name);
  /// An ECDSA P-256 / SHA-256 signature of `data`, DER (at most 72 bytes). With a nonce that
  /// prepare() computed ahead, about 2 µs; else the nonce is computed now (about 20 µs).
  /// @throws std::runtime_error when OpenSSL fails (it does not for a loaded key).
  std::vector<std::uint8_t> sign(std::span<const std::uint8_t> data) const;
  /// Computes the next signature's nonce (k, its inverse and r = x(k·G): the costly part) unless
  /// one is ready; each is used once. load() prepares the first. Call it off the path a signature
  /// delays, e.g. after the signed delta was sent (Admission::prepare()).
  void prepare() const;
  const std::string& name() const { return name_; }

  Signer(Signer&&) noexcept;
  Signer& operator=(Signer&&) noexcept;
  Signer(const Signer&) = delete;
  Signer& operator=(const Signer&) = delete;
  ~Signer();

 private:
  Signer() = default;
  std::string name_;
  internal::KeyPtr key_;
  std::unique_ptr<internal::SignAhead> ahead_;
};

/// Every agent certificate in DIR/agents/*/cert.pem that verifies against DIR/ca.pem and
/// DIR/crl.pem and is valid now, by agent id (fnv1a64 of its CN).
class IdentityBook {
 public:
  /// @returns kNotFound when DIR/ca.pem is missing, kMalformed when it or DIR/crl.pem cannot be
  /// read. A single bad agent certificate is left out (verify() then says why), not an error.
  static Result<IdentityBook> load(const std::string& dir);

  /// Ok if `sig` is a valid signature of `data` by the agent whose id is `agent`.
  /// @returns kNotFound (unknown agent), kRefused (its certificate is revoked, expired, not
  /// signed by the CA, or has expired since load), kRefused (bad signature).
  Status verify(std::uint64_t agent, std::span<const std::uint8_t> data,
                std::span<const std::uint8_t> sig) const;
  /// The agent's name (its certificate's CN), if known and valid.
  std::optional<std::string> name_of(std::uint64_t agent) const;
  /// Whether `participant` (a DDS Security participant's GUID, 16 bytes) is one that agent
  /// `agent`'s certificate authenticated: DDS Security derives a participant GUID's first 48 bits
  /// from the SHA-256 of its certificate's subject, and Cyclone refuses at
  /// the handshake a peer whose GUID does not match its certificate. False for an unknown, revoked
  /// or expired agent and for anything but 16 bytes.
  bool authenticates(std::uint64_t agent, std::span<const std::uint8_t> participant) const;
  /// Re-reads the directory (e.g. an agent added or revoked since load); rate limiting is the
  /// caller's job. On error the book is unchanged.
  Status reload();
  /// How many agents the book trusts.
  std::size_t size() const { return known_.size(); }

  IdentityBook(IdentityBook&&) noexcept;
  IdentityBook& operator=(IdentityBook&&) noexcept;
  IdentityBook(const IdentityBook&) = delete;
  IdentityBook& operator=(const IdentityBook&) = delete;
  ~IdentityBook();

 private:
  IdentityBook() = default;
  struct Entry {
    std::string name;
    internal::KeyPtr key;
    std::int64_t not_after = 0;  // seconds since the epoch
    std::string not_after_text;
    std::array<std::uint8_t, 6> participant_prefix{};
  };
  std::string dir_;
  std::map<std::uint64_t, Entry> known_;
  std::map<std::uint64_t, std::string> refused_;  // agent id -> why it is not in known_
};

}  // namespace quiver::agents::inline replica::security
