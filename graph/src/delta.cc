// GraphDelta, a fragment of the graph CRDT's state: cleared (whole or its ops), its changes counted, and
// another appended to it.
#include "quiver/graph/delta.h"

namespace quiver::graph {

void GraphDelta::clear() {
  kind = Kind::kDelta;
  origin = ReplicaId{};
  seq_lo = seq_hi = 0;
  context.clear();
  clear_ops();
  rule.clear();
  binding.clear();
}

void GraphDelta::clear_ops() {
  nodes.clear();
  edges.clear();
  attrs.clear();
  removed.clear();
  added.clear();
  values.clear();
  claims.clear();
  samples.clear();
  keep.clear();
}

std::size_t GraphDelta::change_count() const {
  std::size_t n = 0;
  for (const auto& a : attrs) n += a.added.size() + a.removed.size();
  for (const auto& node : nodes)
    n += (node.has_header ? 1 : 0) + (node.removed ? 1 : 0) + node.claim_added.size() +
         node.claim_removed.size() + node.samples.size();
  for (const auto& e : edges) n += e.added.size() + e.removed.size();
  return n;
}

void GraphDelta::append(const GraphDelta& o) {
  auto shift = [](Span s, std::size_t by) {
    return Span{static_cast<std::uint32_t>(s.begin + by), static_cast<std::uint32_t>(s.end + by)};
  };
  const std::size_t rem0 = removed.size(), add0 = added.size(), val0 = values.size(),
                    cl0 = claims.size(), sm0 = samples.size(), at0 = attrs.size();
  removed.insert(removed.end(), o.removed.begin(), o.removed.end());
  added.insert(added.end(), o.added.begin(), o.added.end());
  values.insert(values.end(), o.values.begin(), o.values.end());
  claims.insert(claims.end(), o.claims.begin(), o.claims.end());
  samples.insert(samples.end(), o.samples.begin(), o.samples.end());
  for (AttrOp a : o.attrs) {
    a.removed = shift(a.removed, rem0);
    a.added = shift(a.added, val0);
    attrs.push_back(a);
  }
  for (NodeOp n : o.nodes) {
    n.attrs = shift(n.attrs, at0);
    n.claim_removed = shift(n.claim_removed, rem0);
    n.claim_added = shift(n.claim_added, cl0);
    n.samples = shift(n.samples, sm0);
    nodes.push_back(std::move(n));
  }
  for (EdgeOp e : o.edges) {
    e.removed = shift(e.removed, rem0);
    e.added = shift(e.added, add0);
    e.attrs = shift(e.attrs, at0);
    edges.push_back(e);
  }
  context.join(o.context);
  keep.insert(keep.end(), o.keep.begin(), o.keep.end());
  // A joined interval applies several rules: a single claim no longer describes it.
  rule.clear();
  binding.clear();
}

}  // namespace quiver::graph
