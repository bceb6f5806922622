// Graph-level identity: payloads signed with an agent's DDS Security key, and verified against the certificates
// the CA signed and has not revoked.
#include "quiver/agents/replica/security/identity.h"

#include <openssl/ec.h>
#include <openssl/evp.h>
#include <openssl/sha.h>
#include <openssl/x509.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "openssl_util.h"
#include "quiver/agents/replica/security/keys.h"
#include "sign_ahead.h"
#include "quiver/base/hash.h"

namespace quiver::agents::inline replica::security {

namespace internal {
void KeyDeleter::operator()(evp_pkey_st* key) const { EVP_PKEY_free(key); }
}  // namespace internal

namespace {

namespace fs = std::filesystem;
using namespace internal;

std::string hex_id(std::uint64_t id) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(id));
  return buf;
}

bool is_p256(EVP_PKEY* key) {
  char group[32] = {};
  std::size_t len = 0;
  return EVP_PKEY_is_a(key, "EC") &&
         EVP_PKEY_get_utf8_string_param(key, "group", group, sizeof group, &len) == 1 &&
         std::string(group, len) == "prime256v1";
}

// The first 6 bytes of the GUID of every DDS Security participant `cert` authenticates: a flag bit,
// then the first 47 bits of the SHA-256 of its DER-encoded subject (OMG DDS Security 1.1, 9.3.3;
// Cyclone's authentication plugin computes the same when it creates a participant and checks it at
// every handshake).
std::array<std::uint8_t, 6> prefix_of(X509* cert) {
  std::array<std::uint8_t, 6> out{};
  unsigned char* der = nullptr;
  const int len = i2d_X509_NAME(X509_get_subject_name(cert), &der);
  if (len <= 0) return out;  // all zero: matches no participant (the flag bit is always set)
  unsigned char hash[SHA256_DIGEST_LENGTH];
  SHA256(der, static_cast<std::size_t>(len), hash);
  OPENSSL_free(der);
  std::uint8_t carry = 0x80;  // the flag bit that marks a prefix derived from a certificate
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<std::uint8_t>(carry | (hash[i] >> 1));
    carry = static_cast<std::uint8_t>(hash[i] << 7);
  }
  return out;
}

}  // namespace

// ------------------------------------------------------------------ Signer

Signer::~Signer() = default;
Signer::Signer(Signer&&) noexcept = default;
Signer& Signer::operator=(Signer&&) noexcept = default;

Result<Signer> Signer::load(const std::string& dir, const std::string& name) {
  if (!is_valid_agent_name(name))
    return make_error(ErrorCode::kInvalidArgument,
                      "Signer::load(): agent name '" + name + "' is not valid");
  const std::string path = (fs::path(dir) / "agents" / name / "key.pem").string();
  if (!exists(path))
    return make_error(ErrorCode::kNotFound,
                      "Signer::load(): no key for agent " + name + " in " + dir + " (" + path +
                          "): run `quiver keys add-agent " + name + " --dir " + dir + "`");
  auto key = load_key(path);
  if (!key.ok()) return make_error(key.error().code, "Signer::load(): " + key.error().message);
  if (!is_p256(key->get()))
    return make_error(ErrorCode::kMalformed,
                      "Signer::load(): '" + path + "' is not an EC P-256 key");
  Signer s;
  s.name_ = name;
  s.key_.reset(key->release());
  try {
    s.ahead_ = std::make_unique<SignAhead>(s.key_.get());
    s.ahead_->prepare();
  } catch (const std::runtime_error& e) {
    return make_error(ErrorCode::kMalformed, "Signer::load(): '" + path + "': " + e.what());
  }
  return s;
}

std::vector<std::uint8_t> Signer::sign(std::span<const std::uint8_t> data) const { return ahead_->sign(data); }

void Signer::prepare() const { ahead_->prepare(); }

// ------------------------------------------------------------------ IdentityBook

IdentityBook::IdentityBook(IdentityBook&&) noexcept = default;
IdentityBook& IdentityBook::operator=(IdentityBook&&) noexcept = default;
IdentityBook::~IdentityBook() = default;

Result<IdentityBook> IdentityBook::load(const std::string& dir) {
  IdentityBook book;
  book.dir_ = dir;
  if (Status s = book.reload(); !s.ok()) return s.error();
  return book;
}

Status IdentityBook::reload() {
  const fs::path root(dir_);
  if (!exists((root / "ca.pem").string()))
    return make_error(ErrorCode::kNotFound, "IdentityBook: '" + dir_ + "' holds no CA (ca.pem)");
  auto ca = load_cert((root / "ca.pem").string());
  if (!ca.ok()) return make_error(ca.error().code, "IdentityBook: " + ca.error().message);
  Crl crl;
  if (exists((root / "crl.pem").string())) {
    auto loaded = load_crl((root / "crl.pem").string());
    if (!loaded.ok())
      return make_error(loaded.error().code, "IdentityBook: " + loaded.error().message);
    crl = std::move(*loaded);
  }
  std::map<std::uint64_t, Entry> known;
  std::map<std::uint64_t, std::string> refused;
  const std::time_t now = std::time(nullptr);
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(root / "agents", ec)) {
    const std::string folder = e.path().filename().string();
    const fs::path cert_path = e.path() / "cert.pem";
    if (!e.is_directory() || !exists(cert_path.string())) continue;
    auto cert = load_cert(cert_path.string());
    const std::uint64_t folder_id = fnv1a64(folder);
    if (!cert.ok()) {
      refused[folder_id] = cert.error().message;
      continue;
    }
    const std::string name = common_name(cert->get());
    const std::uint64_t id = fnv1a64(name);
    if (name != folder) {
      refused[folder_id] = "the certificate in " + e.path().string() + " is for '" + name + "'";
      continue;
    }
    if (Status s = check_cert(name, cert->get(), ca->get(), crl.get(), now); !s.ok()) {
      refused[id] = s.error().message;
      continue;
    }
    if (auto it = known.find(id); it != known.end()) {
      // Two names with one FNV-1a hash: neither can be told apart from the other.
      refused[id] = "agents " + it->second.name + " and " + name + " share the id " + hex_id(id);
      known.erase(it);
      continue;
    }
    Entry entry;
    entry.name = name;
    entry.key.reset(X509_get_pubkey(cert->get()));
    if (!entry.key) {
      refused[id] = "agent " + name + "'s certificate holds no public key";
      continue;
    }
    entry.not_after = epoch_seconds(X509_get0_notAfter(cert->get()));
    entry.not_after_text = time_text(X509_get0_notAfter(cert->get()));
    entry.participant_prefix = prefix_of(cert->get());
    known.emplace(id, std::move(entry));
  }
  if (ec && ec != std::errc::no_such_file_or_directory)
    return make_error(ErrorCode::kIo, "IdentityBook: cannot list " + (root / "agents").string() +
                                          ": " + ec.message());
  known_ = std::move(known);
  refused_ = std::move(refused);
  return {};
}

Status IdentityBook::verify(std::uint64_t agent, std::span<const std::uint8_t> data,
                            std::span<const std::uint8_t> sig) const {
  auto it = known_.find(agent);
  if (it == known_.end()) {
    auto why = refused_.find(agent);
    if (why != refused_.end())
      return make_error(ErrorCode::kRefused,
                        "IdentityBook::verify: agent " + hex_id(agent) + ": " + why->second);
    return make_error(ErrorCode::kNotFound, "IdentityBook::verify: unknown agent " + hex_id(agent) +
                                                " (no valid certificate under " + dir_ +
                                                "/agents)");
  }
  const Entry& e = it->second;
  if (static_cast<std::int64_t>(std::time(nullptr)) > e.not_after)
    return make_error(ErrorCode::kRefused, "IdentityBook::verify: agent " + e.name +
                                               "'s certificate expired on " + e.not_after_text);
  MdCtx ctx(EVP_MD_CTX_new());
  if (!ctx || EVP_DigestVerifyInit(ctx.get(), nullptr, EVP_sha256(), nullptr, e.key.get()) != 1)
    return ssl_error(ErrorCode::kInternal, "IdentityBook::verify: EVP_DigestVerifyInit");
  const int ok = EVP_DigestVerify(ctx.get(), sig.data(), sig.size(), data.data(), data.size());
  ssl_errors();  // a malformed signature leaves decoding errors behind
  if (ok != 1)
    return make_error(ErrorCode::kRefused, "IdentityBook::verify: bad signature from agent " +
                                               e.name + " (" + std::to_string(sig.size()) +
                                               " bytes over " + std::to_string(data.size()) +
                                               " bytes)");
  return {};
}

bool IdentityBook::authenticates(std::uint64_t agent, std::span<const std::uint8_t> participant) const {
  auto it = known_.find(agent);
  if (participant.size() != 16 || it == known_.end() ||
      static_cast<std::int64_t>(std::time(nullptr)) > it->second.not_after)
    return false;
  return std::equal(it->second.participant_prefix.begin(), it->second.participant_prefix.end(), participant.begin());
}

std::optional<std::string> IdentityBook::name_of(std::uint64_t agent) const {
  auto it = known_.find(agent);
  if (it == known_.end() || static_cast<std::int64_t>(std::time(nullptr)) > it->second.not_after)
    return std::nullopt;
  return it->second.name;
}

}  // namespace quiver::agents::inline replica::security
