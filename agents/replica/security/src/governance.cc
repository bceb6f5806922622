// What a DDS Security governance document promises about origins: whether every topic's submessages
// carry receiver-specific MACs (origin authentication), which the fast path of the admission needs.
#include <openssl/bio.h>
#include <openssl/pem.h>
#include <openssl/x509_vfy.h>

#include <pugixml.hpp>
#include <string_view>

#include "openssl_util.h"
#include "quiver/agents/replica/security/keys.h"

namespace quiver::agents::inline replica::security {

using namespace internal;

namespace {

// The document inside an S/MIME (PKCS7_TEXT, detached) file the CA signed, checked against it.
Result<std::string> signed_text(const std::string& p7s_path, const std::string& ca_path) {
  const std::string fn = "governance " + p7s_path;
  auto ca = load_cert(ca_path);
  if (!ca.ok()) return ca.error();
  Bio in(BIO_new_file(p7s_path.c_str(), "r"));
  if (!in) return ssl_error(ErrorCode::kNotFound, fn + ": cannot open");
  BIO* content = nullptr;
  Pkcs7 p7(SMIME_read_PKCS7(in.get(), &content));
  Bio content_owner(content);
  if (!p7 || content == nullptr) return ssl_error(ErrorCode::kMalformed, fn + ": not an S/MIME signed document");
  Store store(X509_STORE_new());
  Bio out(BIO_new(BIO_s_mem()));
  if (!store || !out || X509_STORE_add_cert(store.get(), ca->get()) != 1)
    return ssl_error(ErrorCode::kInternal, fn + ": X509_STORE");
  if (PKCS7_verify(p7.get(), nullptr, store.get(), content, out.get(), PKCS7_TEXT) != 1)
    return ssl_error(ErrorCode::kRefused, fn + ": not signed by the CA in " + ca_path);
  char* data = nullptr;
  const long n = BIO_get_mem_data(out.get(), &data);
  return std::string(data, n > 0 ? static_cast<std::size_t>(n) : 0);
}

}  // namespace

Result<bool> governance_authenticates_origins(const std::string& governance_p7s, const std::string& ca_pem) {
  auto text = signed_text(governance_p7s, ca_pem);
  if (!text.ok()) return text.error();
  pugi::xml_document doc;
  if (pugi::xml_parse_result r = doc.load_string(text->c_str()); !r)
    return make_error(ErrorCode::kMalformed, "governance " + governance_p7s + ": " + r.description() +
                                                 " at offset " + std::to_string(r.offset));
  bool any = false;
  for (const pugi::xpath_node& rule : doc.select_nodes("//topic_rule")) {
    const std::string_view kind = rule.node().child("metadata_protection_kind").text().as_string();
    if (!kind.ends_with("_WITH_ORIGIN_AUTHENTICATION")) return false;
    any = true;
  }
  return any;
}

}  // namespace quiver::agents::inline replica::security
