// The schema as a replica's Admission: received deltas and states checked after the admission it
// wraps, and the local commit check.
#include "quiver/agents/rules/schema/schema_admission.h"

#include "quiver/agents/rules/schema/schema_checks.h"

namespace quiver::agents::inline rules::schema {

SchemaAdmission::SchemaAdmission(std::shared_ptr<const Schema> schema, Admission* inner)
    : schema_(std::move(schema)), inner_(inner) {}

std::vector<std::uint8_t> SchemaAdmission::sign(std::span<const std::uint8_t> payload) {
  return inner_ != nullptr ? inner_->sign(payload) : std::vector<std::uint8_t>{};
}

Status SchemaAdmission::admit_delta(const graph::GraphDelta& d, std::span<const std::uint8_t> payload,
                                    std::span<const std::uint8_t> signature, std::span<const std::uint8_t> sender) {
  if (inner_ != nullptr)
    if (Status s = inner_->admit_delta(d, payload, signature, sender); !s.ok()) return s;
  return check_delta(*schema_, d);
}

Status SchemaAdmission::admit_state(const PeerId& from, const graph::GraphDelta& state) {
  if (inner_ != nullptr)
    if (Status s = inner_->admit_state(from, state); !s.ok()) return s;
  return check_state(*schema_, state);
}

graph::Graph::CommitValidator SchemaAdmission::commit_check(std::uint64_t self,
                                                            graph::Graph::CommitValidator then) const {
  return [schema = schema_, self, then = std::move(then)](const graph::Graph& g, const std::vector<graph::TxnOp>& ops) {
    if (then)
      if (Status s = then(g, ops); !s.ok()) return s;
    return check_transaction(*schema, self, g, ops);
  };
}

std::function<bool(graph::Symbol)> SchemaAdmission::type_change_check() const {
  return [schema = schema_](graph::Symbol attr) { return schema->allows_type_change(attr); };
}

void SchemaAdmission::install(graph::Graph& g, Replicator& r, graph::Graph::CommitValidator then) {
  r.set_admission(this);
  g.set_permission_check(commit_check(g.replica().agent, std::move(then)));
  g.set_type_change_check(type_change_check());
}

}  // namespace quiver::agents::inline rules::schema
