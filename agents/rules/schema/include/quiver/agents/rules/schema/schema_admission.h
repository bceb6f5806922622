#pragma once
/// @file
/// The schema as a replica's Admission (agents/replica/replication/admission.h): a received delta
/// or state that breaks it is reported and never applied; its interval counts as received, as
/// with any refusal, so replicas that all refuse it stay equal. It wraps the Admission that
/// replica would have had otherwise (e.g. the permissions' PolicyAdmission), which signs what
/// the replica publishes and is asked first.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "quiver/agents/replica/replication/admission.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/rules/schema/schema.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::schema {

class SchemaAdmission final : public Admission {
 public:
  /// `inner` (may be null) must outlive this.
  SchemaAdmission(std::shared_ptr<const Schema> schema, Admission* inner);

  std::vector<std::uint8_t> sign(std::span<const std::uint8_t> payload) override;
  void prepare() override {
    if (inner_ != nullptr) inner_->prepare();
  }
  Status admit_delta(const graph::GraphDelta& d, std::span<const std::uint8_t> payload,
                     std::span<const std::uint8_t> signature, std::span<const std::uint8_t> sender) override;
  Status admit_state(const PeerId& from, const graph::GraphDelta& state) override;

  /// The check for Graph::set_permission_check of the replica whose agent id is `self`, after
  /// `then` (the inner admission's own check; may be empty).
  graph::Graph::CommitValidator commit_check(std::uint64_t self, graph::Graph::CommitValidator then = {}) const;
  /// For Graph::set_type_change_check: whether an attribute's value type may change.
  std::function<bool(graph::Symbol)> type_change_check() const;
  /// Makes this `r`'s Admission and `g`'s permission check (after `then`, the inner admission's
  /// own commit check) and type-change check. Owner thread, before r.start().
  void install(graph::Graph& g, Replicator& r, graph::Graph::CommitValidator then = {});
  const Schema& schema() const { return *schema_; }

 private:
  std::shared_ptr<const Schema> schema_;
  Admission* inner_;
};

}  // namespace quiver::agents::inline rules::schema
