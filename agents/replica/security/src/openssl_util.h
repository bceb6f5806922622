#pragma once
// OpenSSL's C API (libcrypto 3.0), wrapped once: owning pointers, errors as quiver::Error, PEM
// files in and out, certificate checks.

#include <openssl/evp.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>

#include <ctime>
#include <memory>
#include <string>

#include "quiver/base/result.h"

namespace quiver::agents::inline replica::security::internal {

template <auto Free>
struct Freer {
  template <class T>
  void operator()(T* p) const {
    Free(p);
  }
};
using Pkey = std::unique_ptr<EVP_PKEY, Freer<EVP_PKEY_free>>;
using Cert = std::unique_ptr<X509, Freer<X509_free>>;
using Crl = std::unique_ptr<X509_CRL, Freer<X509_CRL_free>>;
using Bio = std::unique_ptr<BIO, Freer<BIO_free_all>>;
using Pkcs7 = std::unique_ptr<PKCS7, Freer<PKCS7_free>>;
using Store = std::unique_ptr<X509_STORE, Freer<X509_STORE_free>>;
using StoreCtx = std::unique_ptr<X509_STORE_CTX, Freer<X509_STORE_CTX_free>>;
using MdCtx = std::unique_ptr<EVP_MD_CTX, Freer<EVP_MD_CTX_free>>;

/// Drains OpenSSL's error queue of this thread into one line ("" when empty).
std::string ssl_errors();
/// `code` with "what: <OpenSSL's errors>".
Error ssl_error(ErrorCode code, const std::string& what);

bool exists(const std::string& path);
Result<std::string> read_file(const std::string& path);
/// Writes `path` whole (through a temporary file and a rename); `secret`: mode 0600, else 0644.
Status write_file(const std::string& path, const std::string& contents, bool secret);

Result<Pkey> new_p256_key();
Result<Pkey> load_key(const std::string& path);
Result<Cert> load_cert(const std::string& path);
Result<Crl> load_crl(const std::string& path);
Result<std::string> key_pem(EVP_PKEY* key);
Result<std::string> cert_pem(X509* cert);
Result<std::string> crl_pem(X509_CRL* crl);

/// "2026-11-23 10:00:00 UTC".
std::string time_text(const ASN1_TIME* t);
/// "2026-11-23T10:00:00Z" (xs:dateTime, as DDS Security documents want it).
std::string xml_time(const ASN1_TIME* t);
/// Seconds since the epoch.
std::int64_t epoch_seconds(const ASN1_TIME* t);
std::string common_name(X509* cert);
std::string serial_hex(X509* cert);

/// Is `cert` (agent `name`'s) signed by `ca`, not revoked by `crl` (may be null) and valid at
/// `now`? kRefused errors say why in words ("agent NAME's certificate expired on ...").
Status check_cert(const std::string& name, X509* cert, X509* ca, X509_CRL* crl, std::time_t now);

/// `text` S/MIME signed (detached, PKCS7_TEXT) by `cert`/`key`: the form Cyclone's access control
/// plugin reads (`openssl smime -sign -text`).
Result<std::string> smime_sign(const std::string& text, X509* cert, EVP_PKEY* key);

}  // namespace quiver::agents::inline replica::security::internal
