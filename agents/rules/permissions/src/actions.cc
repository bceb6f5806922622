// A change seen as the policy's actions: a local transaction, a delta or a state fragment checked action by
// action against its author.
#include "quiver/agents/rules/permissions/actions.h"

#include <unordered_map>

namespace quiver::agents::inline rules::permissions {
namespace {

using graph::GraphDelta;
using graph::NodeId;
using graph::Symbol;
using graph::TxnOp;

Symbol lock_attr() {
  static const Symbol s("__lock");
  return s;
}

// A node attribute write: the lock attribute is the lock action on the scope's root type.
Status node_write(const Policy& p, std::uint64_t agent, Symbol type, Symbol attr) {
  if (attr == lock_attr()) return p.check(agent, Action::kLock, type, Symbol());
  return p.check(agent, Action::kWrite, type, attr);
}

Status with_where(Status s, const std::string& where) {
  if (s.ok()) return s;
  return make_error(s.error().code, s.error().message + " (" + where + ")");
}

}  // namespace

Status check_transaction(const Policy& p, std::uint64_t agent, const graph::Graph& g, const std::vector<TxnOp>& ops) {
  std::unordered_map<NodeId, Symbol> created;  // nodes this transaction creates
  auto type_of = [&](NodeId id) {
    auto it = created.find(id);
    return it != created.end() ? it->second : g.type_of(id);
  };
  for (const TxnOp& op : ops) {
    Status s;
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode:
        created.emplace(op.node, op.type);
        s = p.check(agent, Action::kCreate, op.type, Symbol());
        for (const auto& a : op.attrs)
          if (s.ok()) s = node_write(p, agent, op.type, a.first);
        break;
      case TxnOp::Kind::kDeleteNode: s = p.check(agent, Action::kDelete, type_of(op.node), Symbol()); break;
      case TxnOp::Kind::kSetAttr:
      case TxnOp::Kind::kRemoveAttr: s = node_write(p, agent, type_of(op.node), op.attr); break;
      case TxnOp::Kind::kInsertEdge:
        s = p.check(agent, Action::kEdge, op.type, Symbol());
        for (const auto& a : op.attrs)
          if (s.ok()) s = p.check(agent, Action::kWrite, op.type, a.first);
        break;
      case TxnOp::Kind::kDeleteEdge: s = p.check(agent, Action::kEdge, op.type, Symbol()); break;
      case TxnOp::Kind::kSetEdgeAttr:
      case TxnOp::Kind::kRemoveEdgeAttr: s = p.check(agent, Action::kWrite, op.type, op.attr); break;
      case TxnOp::Kind::kSetRt:
      case TxnOp::Kind::kRemoveRt: s = p.check(agent, Action::kRt, type_of(op.node), Symbol()); break;
    }
    if (!s.ok()) return s;
  }
  return {};
}

Status check_delta(const Policy& p, const GraphDelta& d) {
  const std::uint64_t agent = d.origin.agent;
  for (const GraphDelta::NodeOp& n : d.nodes) {
    const std::string where = "node " + n.id.to_string();
    if (n.has_header)
      if (Status s = p.check(agent, Action::kCreate, n.type, Symbol()); !s.ok()) return with_where(s, where);
    if (n.removed)
      if (Status s = p.check(agent, Action::kDelete, n.type, Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i)
      if (Status s = node_write(p, agent, n.type, d.attrs[i].name); !s.ok()) return with_where(s, where);
    if (!n.claim_added.empty() || !n.claim_removed.empty() || !n.samples.empty())
      if (Status s = p.check(agent, Action::kRt, n.type, Symbol()); !s.ok()) return with_where(s, where);
  }
  for (const GraphDelta::EdgeOp& e : d.edges) {
    const std::string where = "edge " + e.key.to_string();
    if (!e.added.empty() || !e.removed.empty())
      if (Status s = p.check(agent, Action::kEdge, e.key.type, Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i)
      if (Status s = p.check(agent, Action::kWrite, e.key.type, d.attrs[i].name); !s.ok()) return with_where(s, where);
  }
  return {};
}

Status check_state(const Policy& p, const GraphDelta& st) {
  for (const GraphDelta::NodeOp& n : st.nodes) {
    const std::string where = "node " + n.id.to_string() + " in a state";
    if (n.has_header)
      if (Status s = p.check(n.id.dot.replica.agent, Action::kCreate, n.type, Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i) {
      const GraphDelta::AttrOp& a = st.attrs[i];
      for (std::uint32_t v = a.added.begin; v < a.added.end; ++v)
        if (Status s = node_write(p, st.values[v].dot.replica.agent, n.type, a.name); !s.ok()) return with_where(s, where);
    }
    for (std::uint32_t c = n.claim_added.begin; c < n.claim_added.end; ++c)
      if (Status s = p.check(st.claims[c].dot.replica.agent, Action::kRt, n.type, Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t c = n.samples.begin; c < n.samples.end; ++c)
      if (Status s = p.check(st.samples[c].dot.replica.agent, Action::kRt, n.type, Symbol()); !s.ok()) return with_where(s, where);
  }
  for (const GraphDelta::EdgeOp& e : st.edges) {
    const std::string where = "edge " + e.key.to_string() + " in a state";
    for (std::uint32_t i = e.added.begin; i < e.added.end; ++i)
      if (Status s = p.check(st.added[i].replica.agent, Action::kEdge, e.key.type, Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i) {
      const GraphDelta::AttrOp& a = st.attrs[i];
      for (std::uint32_t v = a.added.begin; v < a.added.end; ++v)
        if (Status s = p.check(st.values[v].dot.replica.agent, Action::kWrite, e.key.type, a.name); !s.ok()) return with_where(s, where);
    }
  }
  return {};
}

}  // namespace quiver::agents::inline rules::permissions
