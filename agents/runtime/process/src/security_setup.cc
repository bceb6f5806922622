// A DDS replica made secure from a key directory: DDS Security with the agent's credentials, and an admission
// that signs its deltas and checks everyone's against the certificates and the policy.
#include "quiver/agents/runtime/process/security_setup.h"

#include <chrono>
#include <filesystem>
#include <memory>

#include "quiver/agents/rules/permissions/policy_admission.h"
#include "quiver/agents/replica/security/identity.h"
#include "quiver/agents/replica/security/keys.h"

namespace quiver::agents::inline runtime {

Status enable_security(DdsReplicaOptions& o, const std::string& dir) {
  auto files = security::agent_files(dir, o.name);
  if (!files.ok()) return files.error();
  auto signer = security::Signer::load(dir, o.name);
  if (!signer.ok()) return signer.error();
  auto book = security::IdentityBook::load(dir);
  if (!book.ok()) return book.error();
  const std::filesystem::path policy_file = std::filesystem::path(dir) / "policy.json";
  std::error_code ec;
  auto policy = std::filesystem::exists(policy_file, ec) ? permissions::Policy::load(policy_file.string())
                                                         : Result<permissions::Policy>(permissions::Policy::allow_all());
  if (!policy.ok()) return policy.error();
  // Errors name every agent with credentials, not only those the rules name.
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(dir) / "agents", ec))
    if (entry.is_directory()) policy->learn_name(entry.path().filename().string());

  auto key = std::make_shared<security::Signer>(std::move(*signer));
  auto identities = std::make_shared<security::IdentityBook>(std::move(*book));
  auto last_reload = std::make_shared<std::chrono::steady_clock::time_point>();
  auto sign = [key](std::span<const std::uint8_t> payload) { return key->sign(payload); };
  // An agent added after this one started: the directory is read again, at most once a second.
  auto verify = [identities, last_reload](std::uint64_t agent, std::span<const std::uint8_t> data,
                                          std::span<const std::uint8_t> sig) {
    Status s = identities->verify(agent, data, sig);
    if (s.ok() || s.error().code != ErrorCode::kNotFound) return s;
    const auto now = std::chrono::steady_clock::now();
    if (now - *last_reload < std::chrono::seconds(1)) return s;
    *last_reload = now;
    if (!identities->reload().ok()) return s;
    return identities->verify(agent, data, sig);
  };
  // The fast path: a delta its origin's own participant sent is admitted on that (the transport
  // reports senders only under a governance that authenticates origins; docs/security.md).
  auto sent_by = [identities](std::uint64_t agent, std::span<const std::uint8_t> sender) {
    return identities->authenticates(agent, sender);
  };
  o.dds.security = *files;
  o.permissions = std::make_shared<permissions::PolicyAdmission>(std::move(*policy), sign, verify, sent_by);
  o.permissions->set_prepare([key] { key->prepare(); });
  return {};
}

}  // namespace quiver::agents
