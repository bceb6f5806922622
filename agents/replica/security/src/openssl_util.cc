// OpenSSL's C API wrapped once: owning pointers, errors as quiver::Error, PEM files in and out, certificate
// checks and S/MIME signing.
#include "openssl_util.h"

#include <fcntl.h>
#include <openssl/ec.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace quiver::agents::inline replica::security::internal {

std::string ssl_errors() {
  std::string out;
  char buf[256];
  while (unsigned long e = ERR_get_error()) {
    ERR_error_string_n(e, buf, sizeof buf);
    out += (out.empty() ? "" : "; ") + std::string(buf);
  }
  return out;
}

Error ssl_error(ErrorCode code, const std::string& what) {
  std::string errs = ssl_errors();
  return make_error(code, errs.empty() ? what : what + ": " + errs);
}

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

Result<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return make_error(exists(path) ? ErrorCode::kIo : ErrorCode::kNotFound,
                      "cannot read '" + path + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Status write_file(const std::string& path, const std::string& contents, bool secret) {
  const std::string tmp = path + ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, secret ? 0600 : 0644);
  if (fd < 0)
    return make_error(ErrorCode::kIo, "cannot write '" + tmp + "': " + std::strerror(errno));
  const char* p = contents.data();
  std::size_t left = contents.size();
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      return make_error(ErrorCode::kIo, "cannot write '" + tmp + "': " + std::strerror(err));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    ::unlink(tmp.c_str());
    return make_error(ErrorCode::kIo, "cannot write '" + tmp + "': " + std::strerror(errno));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    return make_error(ErrorCode::kIo,
                      "cannot rename '" + tmp + "' to '" + path + "': " + std::strerror(err));
  }
  return {};
}

Result<Pkey> new_p256_key() {
  Pkey key(EVP_EC_gen("P-256"));
  if (!key) return ssl_error(ErrorCode::kInternal, "EVP_EC_gen(P-256)");
  return key;
}

namespace {
Result<Bio> file_bio(const std::string& path) {
  if (!exists(path)) return make_error(ErrorCode::kNotFound, "'" + path + "' does not exist");
  Bio bio(BIO_new_file(path.c_str(), "r"));
  if (!bio) return ssl_error(ErrorCode::kIo, "cannot read '" + path + "'");
  return bio;
}

Result<std::string> mem_text(BIO* bio) {
  char* data = nullptr;
  long n = BIO_get_mem_data(bio, &data);
  if (n < 0) return ssl_error(ErrorCode::kInternal, "BIO_get_mem_data");
  return std::string(data, static_cast<std::size_t>(n));
}
// One PEM object of the file at `path`, read by OpenSSL's `read` (e.g. PEM_read_bio_X509).
template <class Owned, class Read>
Result<Owned> load_pem(const std::string& path, Read read, const char* what) {
  auto bio = file_bio(path);
  if (!bio.ok()) return bio.error();
  Owned object(read(bio->get(), nullptr, nullptr, nullptr));
  if (!object) return ssl_error(ErrorCode::kMalformed, "'" + path + "' holds no PEM " + what);
  return object;
}
}  // namespace

Result<Pkey> load_key(const std::string& path) { return load_pem<Pkey>(path, PEM_read_bio_PrivateKey, "private key"); }
Result<Cert> load_cert(const std::string& path) { return load_pem<Cert>(path, PEM_read_bio_X509, "certificate"); }
Result<Crl> load_crl(const std::string& path) { return load_pem<Crl>(path, PEM_read_bio_X509_CRL, "CRL"); }

Result<std::string> key_pem(EVP_PKEY* key) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1)
    return ssl_error(ErrorCode::kInternal, "PEM_write_bio_PrivateKey");
  return mem_text(bio.get());
}

Result<std::string> cert_pem(X509* cert) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_X509(bio.get(), cert) != 1)
    return ssl_error(ErrorCode::kInternal, "PEM_write_bio_X509");
  return mem_text(bio.get());
}

Result<std::string> crl_pem(X509_CRL* crl) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_X509_CRL(bio.get(), crl) != 1)
    return ssl_error(ErrorCode::kInternal, "PEM_write_bio_X509_CRL");
  return mem_text(bio.get());
}

std::string time_text(const ASN1_TIME* t) {
  struct tm tm {};
  if (t == nullptr || ASN1_TIME_to_tm(t, &tm) != 1) return "(unreadable time)";
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", &tm);
  return buf;
}

std::string xml_time(const ASN1_TIME* t) {
  struct tm tm {};
  if (t == nullptr || ASN1_TIME_to_tm(t, &tm) != 1) return "";
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::int64_t epoch_seconds(const ASN1_TIME* t) {
  struct tm tm {};
  if (t == nullptr || ASN1_TIME_to_tm(t, &tm) != 1) return 0;
  return static_cast<std::int64_t>(timegm(&tm));
}

std::string common_name(X509* cert) {
  X509_NAME* subject = X509_get_subject_name(cert);
  int i = X509_NAME_get_index_by_NID(subject, NID_commonName, -1);
  if (i < 0) return "";
  ASN1_STRING* s = X509_NAME_ENTRY_get_data(X509_NAME_get_entry(subject, i));
  unsigned char* utf8 = nullptr;
  int n = ASN1_STRING_to_UTF8(&utf8, s);
  if (n < 0) return "";
  std::string out(reinterpret_cast<char*>(utf8), static_cast<std::size_t>(n));
  OPENSSL_free(utf8);
  return out;
}

std::string serial_hex(X509* cert) {
  BIGNUM* bn = ASN1_INTEGER_to_BN(X509_get0_serialNumber(cert), nullptr);
  if (bn == nullptr) return "";
  char* hex = BN_bn2hex(bn);
  std::string out = hex ? hex : "";
  OPENSSL_free(hex);
  BN_free(bn);
  return out;
}

Status check_cert(const std::string& name, X509* cert, X509* ca, X509_CRL* crl, std::time_t now) {
  Store store(X509_STORE_new());
  StoreCtx ctx(X509_STORE_CTX_new());
  if (!store || !ctx || X509_STORE_add_cert(store.get(), ca) != 1)
    return ssl_error(ErrorCode::kInternal, "X509_STORE_add_cert");
  if (crl != nullptr) {
    if (X509_STORE_add_crl(store.get(), crl) != 1)
      return ssl_error(ErrorCode::kInternal, "X509_STORE_add_crl");
    X509_STORE_set_flags(store.get(), X509_V_FLAG_CRL_CHECK);
  }
  if (X509_STORE_CTX_init(ctx.get(), store.get(), cert, nullptr) != 1)
    return ssl_error(ErrorCode::kInternal, "X509_STORE_CTX_init");
  X509_STORE_CTX_set_time(ctx.get(), 0, now);
  const int ok = X509_verify_cert(ctx.get());
  ssl_errors();  // X509_verify_cert may leave entries; the code below says what went wrong
  if (ok == 1) return {};
  const int err = X509_STORE_CTX_get_error(ctx.get());
  const std::string who = "agent " + name + "'s certificate";
  switch (err) {
    case X509_V_ERR_CERT_HAS_EXPIRED:
      return make_error(ErrorCode::kRefused,
                        who + " expired on " + time_text(X509_get0_notAfter(cert)));
    case X509_V_ERR_CERT_NOT_YET_VALID:
      return make_error(ErrorCode::kRefused,
                        who + " is not valid before " + time_text(X509_get0_notBefore(cert)));
    case X509_V_ERR_CERT_REVOKED:
      return make_error(ErrorCode::kRefused,
                        who + " (serial " + serial_hex(cert) + ") was revoked");
    case X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT:
    case X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY:
    case X509_V_ERR_CERT_SIGNATURE_FAILURE:
    case X509_V_ERR_UNABLE_TO_VERIFY_LEAF_SIGNATURE:
      return make_error(ErrorCode::kRefused, who + " is not signed by this CA (" +
                                                 X509_verify_cert_error_string(err) + ")");
    default:
      return make_error(ErrorCode::kRefused,
                        who + " does not verify: " + X509_verify_cert_error_string(err));
  }
}

Result<std::string> smime_sign(const std::string& text, X509* cert, EVP_PKEY* key) {
  const int flags = PKCS7_DETACHED | PKCS7_TEXT;
  Bio in(BIO_new_mem_buf(text.data(), static_cast<int>(text.size())));
  if (!in) return ssl_error(ErrorCode::kInternal, "BIO_new_mem_buf");
  Pkcs7 p7(PKCS7_sign(cert, key, nullptr, in.get(), flags));
  if (!p7) return ssl_error(ErrorCode::kInternal, "PKCS7_sign");
  Bio content(BIO_new_mem_buf(text.data(), static_cast<int>(text.size())));
  Bio out(BIO_new(BIO_s_mem()));
  if (!content || !out || SMIME_write_PKCS7(out.get(), p7.get(), content.get(), flags) != 1)
    return ssl_error(ErrorCode::kInternal, "SMIME_write_PKCS7");
  return mem_text(out.get());
}

}  // namespace quiver::agents::inline replica::security::internal
