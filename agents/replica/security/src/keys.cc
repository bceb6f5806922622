// The credentials of a deployment under DDS Security: the CA, each agent's key, certificate and signed
// permissions, the governance document and the revocation list, as PEM files in one directory.
#include "quiver/agents/replica/security/keys.h"

#include <openssl/bn.h>
#include <openssl/rand.h>
#include <openssl/x509v3.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>
#include <system_error>

#include "openssl_util.h"

namespace quiver::agents::inline replica::security {
namespace {

namespace fs = std::filesystem;
using namespace internal;

constexpr int kCrlNextUpdateDays = 36500;

std::string path_in(const std::string& dir, const std::string& file) {
  return (fs::path(dir) / file).string();
}
std::string agent_dir(const std::string& dir, const std::string& name) {
  return (fs::path(dir) / "agents" / name).string();
}
std::string absolute(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

Error no_ca(const char* fn, const std::string& dir) {
  return make_error(ErrorCode::kNotFound, std::string(fn) + ": '" + dir + "' holds no CA (" +
                                              path_in(dir, "ca.pem") + "): run `quiver keys init " +
                                              dir + "`");
}

Status check_name(const char* fn, const std::string& name) {
  if (is_valid_agent_name(name)) return {};
  return make_error(ErrorCode::kInvalidArgument,
                    std::string(fn) + ": agent name '" + name +
                        "' is not 1 to 64 characters of A-Z a-z 0-9 _ . -");
}

Status add_extension(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value);
  if (ext == nullptr)
    return ssl_error(ErrorCode::kInternal, std::string("X509V3_EXT_conf_nid(") + value + ")");
  const int ok = X509_add_ext(cert, ext, -1);
  X509_EXTENSION_free(ext);
  if (ok != 1) return ssl_error(ErrorCode::kInternal, "X509_add_ext");
  return {};
}

/// A 127-bit random serial (positive, so that every tool prints it alike).
Status set_random_serial(X509* cert) {
  unsigned char bytes[16];
  if (RAND_bytes(bytes, sizeof bytes) != 1) return ssl_error(ErrorCode::kInternal, "RAND_bytes");
  bytes[0] &= 0x7f;
  bytes[0] |= 0x01 << 6;  // never a short serial
  BIGNUM* bn = BN_bin2bn(bytes, sizeof bytes, nullptr);
  const bool ok = bn != nullptr && BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(cert)) != nullptr;
  BN_free(bn);
  if (!ok) return ssl_error(ErrorCode::kInternal, "BN_to_ASN1_INTEGER");
  return {};
}

struct CertSpec {
  std::string common_name;
  bool ca = false;
  std::int64_t not_before_offset_s = 0;  // from now
  std::int64_t lifetime_s = 0;
};

/// A certificate for `key` as `spec` says, signed by `issuer`/`issuer_key` (self-signed when
/// `issuer` is null).
Result<Cert> make_cert(EVP_PKEY* key, const CertSpec& spec, X509* issuer, EVP_PKEY* issuer_key) {
  Cert cert(X509_new());
  if (!cert || X509_set_version(cert.get(), X509_VERSION_3) != 1)
    return ssl_error(ErrorCode::kInternal, "X509_new");
  if (Status s = set_random_serial(cert.get()); !s.ok()) return s.error();
  std::time_t now = std::time(nullptr);
  if (X509_time_adj_ex(X509_getm_notBefore(cert.get()), 0,
                       static_cast<long>(spec.not_before_offset_s), &now) == nullptr ||
      X509_time_adj_ex(X509_getm_notAfter(cert.get()), 0,
                       static_cast<long>(spec.not_before_offset_s + spec.lifetime_s),
                       &now) == nullptr)
    return ssl_error(ErrorCode::kInternal, "X509_time_adj_ex");
  // Most significant first: printed as RFC 2253 (what Cyclone's access control compares with
  // the permissions' subject_name) this is "CN=<name>,O=Quiver".
  X509_NAME* subject = X509_get_subject_name(cert.get());
  auto add = [&](const char* field, const std::string& value) {
    return X509_NAME_add_entry_by_txt(subject, field, MBSTRING_UTF8,
                                      reinterpret_cast<const unsigned char*>(value.c_str()), -1, -1,
                                      0) == 1;
  };
  if (!add("O", "Quiver") || !add("CN", spec.common_name))
    return ssl_error(ErrorCode::kInternal, "X509_NAME_add_entry");
  X509* signer = issuer != nullptr ? issuer : cert.get();
  if (X509_set_issuer_name(cert.get(), X509_get_subject_name(signer)) != 1 ||
      X509_set_pubkey(cert.get(), key) != 1)
    return ssl_error(ErrorCode::kInternal, "X509_set_issuer_name");
  const std::pair<int, const char*> ca_ext[] = {
      {NID_basic_constraints, "critical,CA:TRUE"},
      // digitalSignature besides keyCertSign,cRLSign: the CA signs the governance and
      // permissions documents (S/MIME), and PKCS7_verify, in Cyclone and in `openssl smime
      // -verify`, refuses a signer whose key usage lacks it.
      {NID_key_usage, "critical,digitalSignature,keyCertSign,cRLSign"},
      {NID_subject_key_identifier, "hash"},
  };
  const std::pair<int, const char*> leaf_ext[] = {
      {NID_basic_constraints, "critical,CA:FALSE"},
      {NID_key_usage, "critical,digitalSignature,keyAgreement"},
      {NID_subject_key_identifier, "hash"},
      {NID_authority_key_identifier, "keyid:always"},
  };
  for (const auto& e : spec.ca ? std::span<const std::pair<int, const char*>>(ca_ext)
                               : std::span<const std::pair<int, const char*>>(leaf_ext))
    if (Status s = add_extension(cert.get(), signer, e.first, e.second); !s.ok()) return s.error();
  if (X509_sign(cert.get(), issuer_key, EVP_sha256()) <= 0)
    return ssl_error(ErrorCode::kInternal, "X509_sign");
  return cert;
}

/// A CRL signed by the CA holding `previous`'s entries (if any) and `revoke`'s serial (if any).
Result<Crl> make_crl(X509* ca, EVP_PKEY* ca_key, X509_CRL* previous, X509* revoke) {
  Crl crl(X509_CRL_new());
  if (!crl || X509_CRL_set_version(crl.get(), X509_CRL_VERSION_2) != 1 ||
      X509_CRL_set_issuer_name(crl.get(), X509_get_subject_name(ca)) != 1)
    return ssl_error(ErrorCode::kInternal, "X509_CRL_new");
  std::time_t now = std::time(nullptr);
  ASN1_TIME* last = ASN1_TIME_set(nullptr, now);
  ASN1_TIME* next = X509_time_adj_ex(nullptr, kCrlNextUpdateDays, 0, &now);
  const bool times = last != nullptr && next != nullptr &&
                     X509_CRL_set1_lastUpdate(crl.get(), last) == 1 &&
                     X509_CRL_set1_nextUpdate(crl.get(), next) == 1;
  ASN1_TIME_free(next);
  if (!times) {
    ASN1_TIME_free(last);
    return ssl_error(ErrorCode::kInternal, "X509_CRL_set1_lastUpdate");
  }
  bool ok = true;
  if (previous != nullptr) {
    STACK_OF(X509_REVOKED)* revoked = X509_CRL_get_REVOKED(previous);
    for (int i = 0; ok && i < sk_X509_REVOKED_num(revoked); ++i) {
      X509_REVOKED* copy = X509_REVOKED_dup(sk_X509_REVOKED_value(revoked, i));
      ok = copy != nullptr && X509_CRL_add0_revoked(crl.get(), copy) == 1;
    }
  }
  if (ok && revoke != nullptr) {
    X509_REVOKED* r = X509_REVOKED_new();
    ok = r != nullptr && X509_REVOKED_set_serialNumber(r, X509_get_serialNumber(revoke)) == 1 &&
         X509_REVOKED_set_revocationDate(r, last) == 1 && X509_CRL_add0_revoked(crl.get(), r) == 1;
    if (!ok) X509_REVOKED_free(r);
  }
  ASN1_TIME_free(last);
  if (!ok) return ssl_error(ErrorCode::kInternal, "X509_CRL_add0_revoked");
  if (X509_CRL_sort(crl.get()) != 1 || X509_CRL_sign(crl.get(), ca_key, EVP_sha256()) <= 0)
    return ssl_error(ErrorCode::kInternal, "X509_CRL_sign");
  return crl;
}

// Every DDS domain id (Cyclone's parser refuses ids above 230).
std::string domains_xml(const char* indent) {
  return std::string(indent) +
         "<domains><id_range><min>0</min><max>230</max></id_range></domains>\n";
}

// The OMG DDS Security 1.1 governance document: authenticated participants only, discovery and
// liveliness encrypted, every RTPS message signed, every topic's data and metadata encrypted, its
// metadata with origin authentication (a MAC per receiver, so that no member can send samples
// under another's writers: the admission's fast path relies on it), and its readers and writers
// checked against the permissions.
std::string governance_xml() {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\"\n"
         "     xsi:noNamespaceSchemaLocation=\"http://www.omg.org/spec/DDS-SECURITY/20170901/"
         "omg_shared_ca_governance.xsd\">\n"
         "  <domain_access_rules>\n"
         "    <domain_rule>\n" +
         domains_xml("      ") +
         "      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>\n"
         "      <enable_join_access_control>true</enable_join_access_control>\n"
         "      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>\n"
         "      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>\n"
         "      <rtps_protection_kind>SIGN</rtps_protection_kind>\n"
         "      <topic_access_rules>\n"
         "        <topic_rule>\n"
         "          <topic_expression>*</topic_expression>\n"
         "          <enable_discovery_protection>true</enable_discovery_protection>\n"
         "          <enable_liveliness_protection>true</enable_liveliness_protection>\n"
         "          <enable_read_access_control>true</enable_read_access_control>\n"
         "          <enable_write_access_control>true</enable_write_access_control>\n"
         "          <metadata_protection_kind>ENCRYPT_WITH_ORIGIN_AUTHENTICATION</metadata_protection_kind>\n"
         "          <data_protection_kind>ENCRYPT</data_protection_kind>\n"
         "        </topic_rule>\n"
         "      </topic_access_rules>\n"
         "    </domain_rule>\n"
         "  </domain_access_rules>\n"
         "</dds>\n";
}

// One grant: agent `name` may publish and subscribe to every topic in every partition on every domain, for its
// certificate's validity; anything else is denied.
std::string permissions_xml(const std::string& name, X509* cert) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\"\n"
         "     xsi:noNamespaceSchemaLocation=\"http://www.omg.org/spec/DDS-SECURITY/20170901/"
         "omg_shared_ca_permissions.xsd\">\n"
         "  <permissions>\n"
         "    <grant name=\"quiver_agent_" +
         name +
         "\">\n"
         "      <subject_name>CN=" +
         name +
         ",O=Quiver</subject_name>\n"
         "      <validity>\n"
         "        <not_before>" +
         xml_time(X509_get0_notBefore(cert)) +
         "</not_before>\n"
         "        <not_after>" +
         xml_time(X509_get0_notAfter(cert)) +
         "</not_after>\n"
         "      </validity>\n"
         "      <allow_rule>\n" +
         domains_xml("        ") +
         "        <publish><topics><topic>*</topic></topics><partitions><partition>*</partition></partitions></publish>\n"
         "        <subscribe><topics><topic>*</topic></topics><partitions><partition>*</partition></partitions></subscribe>\n"
         "      </allow_rule>\n"
         "      <default>DENY</default>\n"
         "    </grant>\n"
         "  </permissions>\n"
         "</dds>\n";
}

Status make_dir(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) return make_error(ErrorCode::kIo, "cannot create '" + path + "': " + ec.message());
  return {};
}

struct Ca {
  Cert cert;
  Pkey key;
};

Result<Ca> load_ca(const char* fn, const std::string& dir, bool with_key) {
  if (!exists(path_in(dir, "ca.pem"))) return no_ca(fn, dir);
  Ca ca;
  auto cert = load_cert(path_in(dir, "ca.pem"));
  if (!cert.ok())
    return make_error(cert.error().code, std::string(fn) + ": " + cert.error().message);
  ca.cert = std::move(*cert);
  if (with_key) {
    auto key = load_key(path_in(dir, "ca.key.pem"));
    if (!key.ok())
      return make_error(key.error().code, std::string(fn) + ": " + key.error().message);
    ca.key = std::move(*key);
  }
  return ca;
}

Status prefixed(const char* fn, Status s) {
  if (s.ok()) return s;
  return make_error(s.error().code, std::string(fn) + ": " + s.error().message);
}

struct OutFile {
  const char* name;
  const std::string* text;
  bool secret;  // a private key: mode 0600
};

std::int64_t days_to_s(double days) {
  return static_cast<std::int64_t>(std::llround(days * 86400.0));
}

}  // namespace

bool is_valid_agent_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name == "." || name == "..") return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '.' || c == '-';
  });
}

Status init_keys(const std::string& dir, const KeyOptions& options) {
  constexpr const char* fn = "init_keys()";
  for (const char* file : {"ca.pem", "ca.key.pem"})
    if (exists(path_in(dir, file)))
      return make_error(ErrorCode::kAlreadyExists,
                        std::string(fn) + ": " + path_in(dir, file) +
                            " already exists: refusing to overwrite a CA (every agent it signed "
                            "would lose its trust)");
  if (!(options.ca_valid_days > 0) || !std::isfinite(options.ca_valid_days))
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(fn) + ": ca_valid_days must be positive");
  if (Status s = make_dir(dir); !s.ok()) return prefixed(fn, s);
  auto key = new_p256_key();
  if (!key.ok()) return prefixed(fn, key.error());
  CertSpec spec;
  spec.common_name = "Quiver CA";
  spec.ca = true;
  spec.lifetime_s = days_to_s(options.ca_valid_days);
  auto cert = make_cert(key->get(), spec, nullptr, key->get());
  if (!cert.ok()) return prefixed(fn, cert.error());
  const std::string governance = governance_xml();
  auto signed_governance = smime_sign(governance, cert->get(), key->get());
  if (!signed_governance.ok()) return prefixed(fn, signed_governance.error());
  auto crl = make_crl(cert->get(), key->get(), nullptr, nullptr);
  if (!crl.ok()) return prefixed(fn, crl.error());
  auto key_text = key_pem(key->get());
  auto cert_text = cert_pem(cert->get());
  auto crl_text = crl_pem(crl->get());
  if (!key_text.ok() || !cert_text.ok() || !crl_text.ok())
    return ssl_error(ErrorCode::kInternal, fn);
  // The CA last: a failure before leaves no CA behind, and init can be run again.
  const OutFile files[] = {{"governance.xml", &governance, false},
                           {"governance.p7s", &signed_governance.value(), false},
                           {"crl.pem", &crl_text.value(), false},
                           {"ca.key.pem", &key_text.value(), true},
                           {"ca.pem", &cert_text.value(), false}};
  for (const OutFile& f : files)
    if (Status s = write_file(path_in(dir, f.name), *f.text, f.secret); !s.ok())
      return prefixed(fn, s);
  return {};
}

Status add_agent(const std::string& dir, const std::string& name, const AgentKeyOptions& options) {
  constexpr const char* fn = "add_agent()";
  if (Status s = check_name(fn, name); !s.ok()) return s;
  if (!(options.valid_days > 0) || !std::isfinite(options.valid_days) ||
      !(options.backdate_days >= 0) || !std::isfinite(options.backdate_days))
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(fn) + ": valid_days must be positive and " +
                          "backdate_days not negative (got " + std::to_string(options.valid_days) +
                          ", " + std::to_string(options.backdate_days) + ")");
  auto ca = load_ca(fn, dir, true);
  if (!ca.ok()) return ca.error();
  const std::string folder = agent_dir(dir, name);
  if (exists(folder))
    return make_error(ErrorCode::kAlreadyExists, std::string(fn) + ": agent " + name +
                                                     " already has credentials (" + folder +
                                                     "): revoke them and choose another name");
  auto key = new_p256_key();
  if (!key.ok()) return prefixed(fn, key.error());
  CertSpec spec;
  spec.common_name = name;
  spec.not_before_offset_s = -days_to_s(options.backdate_days);
  spec.lifetime_s = days_to_s(options.valid_days);
  auto cert = make_cert(key->get(), spec, ca->cert.get(), ca->key.get());
  if (!cert.ok()) return prefixed(fn, cert.error());
  const std::string permissions = permissions_xml(name, cert->get());
  auto signed_permissions = smime_sign(permissions, ca->cert.get(), ca->key.get());
  if (!signed_permissions.ok()) return prefixed(fn, signed_permissions.error());
  auto key_text = key_pem(key->get());
  auto cert_text = cert_pem(cert->get());
  if (!key_text.ok() || !cert_text.ok()) return ssl_error(ErrorCode::kInternal, fn);
  if (Status s = make_dir(folder); !s.ok()) return prefixed(fn, s);
  std::error_code ec;
  fs::permissions(folder, fs::perms::owner_all, ec);  // the private key's folder: ours alone
  const OutFile files[] = {{"key.pem", &key_text.value(), true},
                           {"cert.pem", &cert_text.value(), false},
                           {"permissions.xml", &permissions, false},
                           {"permissions.p7s", &signed_permissions.value(), false}};
  for (const OutFile& f : files)
    if (Status s = write_file(path_in(folder, f.name), *f.text, f.secret); !s.ok())
      return prefixed(fn, s);
  return {};
}

Status revoke_agent(const std::string& dir, const std::string& name) {
  constexpr const char* fn = "revoke_agent()";
  if (Status s = check_name(fn, name); !s.ok()) return s;
  auto ca = load_ca(fn, dir, true);
  if (!ca.ok()) return ca.error();
  const std::string cert_path = path_in(agent_dir(dir, name), "cert.pem");
  if (!exists(cert_path))
    return make_error(ErrorCode::kNotFound, std::string(fn) + ": no credentials for agent " + name +
                                                " in " + dir + " (" + cert_path + ")");
  auto cert = load_cert(cert_path);
  if (!cert.ok()) return prefixed(fn, cert.error());
  const std::string crl_path = path_in(dir, "crl.pem");
  auto previous = load_crl(crl_path);
  if (!previous.ok()) return prefixed(fn, previous.error());
  X509_REVOKED* already = nullptr;
  if (X509_CRL_get0_by_serial(previous->get(), &already, X509_get_serialNumber(cert->get())) == 1)
    return {};
  auto crl = make_crl(ca->cert.get(), ca->key.get(), previous->get(), cert->get());
  if (!crl.ok()) return prefixed(fn, crl.error());
  auto text = crl_pem(crl->get());
  if (!text.ok()) return prefixed(fn, text.error());
  return prefixed(fn, write_file(crl_path, *text, false));
}

Result<DdsSecurityFiles> agent_files(const std::string& dir, const std::string& name) {
  constexpr const char* fn = "agent_files()";
  if (Status s = check_name(fn, name); !s.ok()) return s.error();
  const std::string folder = agent_dir(dir, name);
  if (!exists(path_in(folder, "cert.pem")))
    return make_error(ErrorCode::kNotFound, "no credentials for agent " + name + " in " + dir +
                                                ": run `quiver keys add-agent " + name + " --dir " +
                                                dir + "`");
  DdsSecurityFiles f;
  f.identity_ca = absolute(path_in(dir, "ca.pem"));
  f.identity_certificate = absolute(path_in(folder, "cert.pem"));
  f.private_key = absolute(path_in(folder, "key.pem"));
  f.permissions_ca = f.identity_ca;
  f.governance = absolute(path_in(dir, "governance.p7s"));
  f.permissions = absolute(path_in(folder, "permissions.p7s"));
  const std::string crl_path = absolute(path_in(dir, "crl.pem"));
  if (exists(crl_path)) f.crl = crl_path;
  for (const std::string* p : {&f.identity_ca, &f.private_key, &f.governance, &f.permissions})
    if (!exists(*p))
      return make_error(ErrorCode::kNotFound, "the credentials of agent " + name + " in " + dir +
                                                  " are incomplete: " + *p + " is missing");
  auto ca = load_ca(fn, dir, false);
  if (!ca.ok()) return ca.error();
  auto cert = load_cert(f.identity_certificate);
  if (!cert.ok()) return cert.error();
  Crl crl;
  if (!f.crl.empty()) {
    auto loaded = load_crl(f.crl);
    if (!loaded.ok()) return loaded.error();
    crl = std::move(*loaded);
  }
  if (const std::string cn = common_name(cert->get()); cn != name)
    return make_error(ErrorCode::kRefused, "agent " + name + "'s certificate (" +
                                               f.identity_certificate + ") is for '" + cn + "'");
  if (Status s = check_cert(name, cert->get(), ca->cert.get(), crl.get(), std::time(nullptr));
      !s.ok())
    return s.error();
  auto origins = governance_authenticates_origins(f.governance, f.identity_ca);
  if (!origins.ok()) return origins.error();
  f.origin_authentication = *origins;
  return f;
}

Result<std::vector<AgentInfo>> list_agents(const std::string& dir) {
  constexpr const char* fn = "list_agents()";
  auto ca = load_ca(fn, dir, false);
  if (!ca.ok()) return ca.error();
  Crl crl;
  if (exists(path_in(dir, "crl.pem"))) {
    auto loaded = load_crl(path_in(dir, "crl.pem"));
    if (!loaded.ok()) return loaded.error();
    crl = std::move(*loaded);
  }
  std::vector<AgentInfo> out;
  std::error_code ec;
  const fs::path agents = fs::path(dir) / "agents";
  if (!fs::is_directory(agents, ec)) return out;
  for (const fs::directory_entry& e : fs::directory_iterator(agents, ec)) {
    if (!e.is_directory()) continue;
    AgentInfo info;
    info.name = e.path().filename().string();
    auto cert = load_cert((e.path() / "cert.pem").string());
    if (!cert.ok()) {
      info.problem = cert.error().message;
      out.push_back(std::move(info));
      continue;
    }
    X509* c = cert->get();
    info.serial = serial_hex(c);
    info.not_before = time_text(X509_get0_notBefore(c));
    info.not_after = time_text(X509_get0_notAfter(c));
    X509_REVOKED* revoked = nullptr;
    info.expired = X509_cmp_current_time(X509_get0_notAfter(c)) < 0;
    info.revoked =
        crl && X509_CRL_get0_by_serial(crl.get(), &revoked, X509_get_serialNumber(c)) == 1;
    Status s = common_name(c) == info.name
                   ? check_cert(info.name, c, ca->cert.get(), crl.get(), std::time(nullptr))
                   : Status(make_error(ErrorCode::kRefused,
                                       "its certificate is for '" + common_name(c) + "'"));
    info.valid = s.ok();
    if (!s.ok()) info.problem = s.error().message;
    out.push_back(std::move(info));
  }
  std::sort(out.begin(), out.end(),
            [](const AgentInfo& a, const AgentInfo& b) { return a.name < b.name; });
  return out;
}

}  // namespace quiver::agents::inline replica::security
