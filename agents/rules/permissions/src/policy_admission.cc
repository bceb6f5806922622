// The admission of a replica with identities: its deltas signed, a received one admitted only if its origin's
// signature verifies and the policy allows every change in it (state fragments and local commits checked too).
#include "quiver/agents/rules/permissions/policy_admission.h"

#include "quiver/agents/rules/permissions/actions.h"

namespace quiver::agents::inline rules::permissions {

PolicyAdmission::PolicyAdmission(Policy policy, SignFn sign, VerifyFn verify, SenderFn sent_by)
    : policy_(std::move(policy)), sign_(std::move(sign)), verify_(std::move(verify)), sent_by_(std::move(sent_by)) {}

std::vector<std::uint8_t> PolicyAdmission::sign(std::span<const std::uint8_t> payload) {
  return sign_ ? sign_(payload) : std::vector<std::uint8_t>{};
}

Status PolicyAdmission::admit_delta(const graph::GraphDelta& d, std::span<const std::uint8_t> payload,
                                    std::span<const std::uint8_t> signature, std::span<const std::uint8_t> sender) {
  if (verify_) {
    // Signed or not is decided alike on every path, so that an unsigned delta is refused by every
    // replica, the ones it reached straight from its origin too.
    if (signature.empty())
      return make_error(ErrorCode::kPermissionDenied,
                        "it is not signed (agent '" + policy_.agent_name(d.origin.agent) + "' must sign its deltas)");
    // The fast path: the participant that sent it is the origin's own, as DDS Security
    // authenticated it (its GUID binds its certificate, and the governance's origin authentication
    // keeps other members from sending under it), so the signature would tell nothing more.
    if (!sender.empty() && sent_by_ && sent_by_(d.origin.agent, sender)) {
      ++on_sender_;
    } else {
      ++verified_;
      if (Status s = verify_(d.origin.agent, payload, signature); !s.ok())
        return make_error(ErrorCode::kPermissionDenied, "its signature does not hold: " + s.error().message);
    }
  }
  return check_delta(policy_, d);
}

Status PolicyAdmission::admit_state(const PeerId&, const graph::GraphDelta& state) { return check_state(policy_, state); }

graph::Graph::CommitValidator PolicyAdmission::commit_check(std::uint64_t self) const {
  return [this, self](const graph::Graph& g, const std::vector<graph::TxnOp>& ops) {
    return check_transaction(policy_, self, g, ops);
  };
}

}  // namespace quiver::agents::inline rules::permissions
