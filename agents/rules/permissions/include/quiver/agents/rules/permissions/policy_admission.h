#pragma once
/// @file
/// The Admission (agents/replica/replication/admission.h) of a replica that runs with identities: it
/// signs every delta it publishes with its agent's key, and admits a received delta only if its
/// origin's signature verifies (the origin is who it claims to be) and the policy lets that agent
/// make every change in it. State transfers are checked entry by entry against each entry's
/// writer. The keys are agents/replica/security's (Signer, IdentityBook); they come in as functions so
/// that this module does not depend on OpenSSL.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "quiver/agents/rules/permissions/policy.h"
#include "quiver/agents/replica/replication/admission.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::permissions {

class PolicyAdmission final : public Admission {
 public:
  using SignFn = std::function<std::vector<std::uint8_t>(std::span<const std::uint8_t>)>;
  /// Ok iff `sig` is `agent`'s signature of `data`.
  using VerifyFn = std::function<Status(std::uint64_t agent, std::span<const std::uint8_t> data,
                                        std::span<const std::uint8_t> sig)>;
  /// Whether `sender` (Sample::sender) is a participant that `agent`'s certificate authenticated.
  using SenderFn = std::function<bool(std::uint64_t agent, std::span<const std::uint8_t> sender)>;
  /// Without `verify`, origins are taken as they claim (the simulator's policy-only mode). With
  /// `sent_by`, a signed delta whose authenticated sender is its origin's own participant is
  /// admitted without verifying its signature (the fast path, docs/security.md).
  PolicyAdmission(Policy policy, SignFn sign, VerifyFn verify, SenderFn sent_by = {});

  std::vector<std::uint8_t> sign(std::span<const std::uint8_t> payload) override;
  void prepare() override {
    if (prepare_) prepare_();
  }
  /// What prepare() does (e.g. Signer::prepare()); none by default.
  void set_prepare(std::function<void()> f) { prepare_ = std::move(f); }
  Status admit_delta(const graph::GraphDelta& d, std::span<const std::uint8_t> payload,
                     std::span<const std::uint8_t> signature, std::span<const std::uint8_t> sender) override;
  Status admit_state(const PeerId& from, const graph::GraphDelta& state) override;

  const Policy& policy() const { return policy_; }
  /// Deltas whose signature was verified, and deltas admitted on their authenticated sender
  /// without verifying it (the fast path), so far.
  std::uint64_t signatures_verified() const { return verified_; }
  std::uint64_t admitted_on_sender() const { return on_sender_; }
  /// The check for Graph::set_permission_check of the replica whose agent id is `self`.
  graph::Graph::CommitValidator commit_check(std::uint64_t self) const;

 private:
  Policy policy_;
  SignFn sign_;
  VerifyFn verify_;
  SenderFn sent_by_;
  std::function<void()> prepare_;
  std::uint64_t verified_ = 0, on_sender_ = 0;
};

}  // namespace quiver::agents::inline rules::permissions
