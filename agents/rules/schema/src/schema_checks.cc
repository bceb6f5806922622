// A change seen by the schema: a local transaction, a delta or a state fragment, checked entry by
// entry (node types, edge types and ends, attribute values and writers).
#include "quiver/agents/rules/schema/schema_checks.h"

#include <unordered_map>

namespace quiver::agents::inline rules::schema {
namespace {

using graph::GraphDelta;
using graph::NodeId;
using graph::Symbol;
using graph::TxnOp;

Status with_where(Status s, const std::string& where) {
  if (s.ok()) return s;
  return make_error(s.error().code, s.error().message + " (" + where + ")");
}

}  // namespace

Status check_transaction(const Schema& sc, std::uint64_t agent, const graph::Graph& g, const std::vector<TxnOp>& ops) {
  std::unordered_map<NodeId, Symbol> created;  // nodes this transaction creates
  auto type_of = [&](NodeId id) {
    auto it = created.find(id);
    return it != created.end() ? it->second : g.type_of(id);
  };
  auto node = [&](NodeId id) {
    auto n = g.name_of(id);
    return n.empty() ? "node " + id.to_string() : "node '" + n + "'";
  };
  for (const TxnOp& op : ops) {
    Status s;
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode:
        created.emplace(op.node, op.type);
        s = sc.check_node_type(op.type);
        for (const auto& [attr, value] : op.attrs)
          if (s.ok()) s = sc.check_value(agent, op.type, false, attr, value);
        s = with_where(s, "creating node '" + op.name + "'");
        break;
      case TxnOp::Kind::kSetAttr: s = with_where(sc.check_value(agent, type_of(op.node), false, op.attr, op.value), node(op.node)); break;
      case TxnOp::Kind::kInsertEdge:
        s = sc.check_edge(op.type, type_of(op.node), type_of(op.other));
        for (const auto& [attr, value] : op.attrs)
          if (s.ok()) s = sc.check_value(agent, op.type, true, attr, value);
        s = with_where(s, "edge " + node(op.node) + " -> " + node(op.other));
        break;
      case TxnOp::Kind::kSetEdgeAttr:
        s = with_where(sc.check_value(agent, op.type, true, op.attr, op.value),
                       "edge " + node(op.node) + " -[" + op.type.str() + "]-> " + node(op.other));
        break;
      case TxnOp::Kind::kSetRt:
        s = with_where(sc.check_edge(Symbol("RT"), type_of(op.other), type_of(op.node)), "RT placement of " + node(op.node));
        break;
      default: break;  // removals take nothing the schema could refuse
    }
    if (!s.ok()) return s;
  }
  return {};
}

Status check_delta(const Schema& sc, const GraphDelta& d) {
  const std::uint64_t agent = d.origin.agent;
  for (const GraphDelta::NodeOp& n : d.nodes) {
    const std::string where = "node " + (n.name.empty() ? n.id.to_string() : "'" + n.name + "'");
    if (n.has_header)
      if (Status s = sc.check_node_type(n.type); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i) {
      const GraphDelta::AttrOp& a = d.attrs[i];
      for (std::uint32_t v = a.added.begin; v < a.added.end; ++v)
        if (Status s = sc.check_value(agent, n.type, false, a.name, d.values[v].value); !s.ok()) return with_where(s, where);
    }
    if (!n.claim_added.empty())
      if (Status s = sc.check_edge(Symbol("RT"), Symbol(), n.type); !s.ok()) return with_where(s, where);
  }
  for (const GraphDelta::EdgeOp& e : d.edges) {
    const std::string where = "edge " + e.key.to_string();
    if (!e.added.empty())
      if (Status s = sc.check_edge(e.key.type, Symbol(), Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i) {
      const GraphDelta::AttrOp& a = d.attrs[i];
      for (std::uint32_t v = a.added.begin; v < a.added.end; ++v)
        if (Status s = sc.check_value(agent, e.key.type, true, a.name, d.values[v].value); !s.ok()) return with_where(s, where);
    }
  }
  return {};
}

Status check_state(const Schema& sc, const GraphDelta& st) {
  for (const GraphDelta::NodeOp& n : st.nodes) {
    const std::string where = "node " + (n.name.empty() ? n.id.to_string() : "'" + n.name + "'") + " in a state";
    if (n.has_header)
      if (Status s = sc.check_node_type(n.type); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i) {
      const GraphDelta::AttrOp& a = st.attrs[i];
      for (std::uint32_t v = a.added.begin; v < a.added.end; ++v)
        if (Status s = sc.check_value(st.values[v].dot.replica.agent, n.type, false, a.name, st.values[v].value); !s.ok())
          return with_where(s, where);
    }
  }
  for (const GraphDelta::EdgeOp& e : st.edges) {
    const std::string where = "edge " + e.key.to_string() + " in a state";
    if (!e.added.empty())
      if (Status s = sc.check_edge(e.key.type, Symbol(), Symbol()); !s.ok()) return with_where(s, where);
    for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i) {
      const GraphDelta::AttrOp& a = st.attrs[i];
      for (std::uint32_t v = a.added.begin; v < a.added.end; ++v)
        if (Status s = sc.check_value(st.values[v].dot.replica.agent, e.key.type, true, a.name, st.values[v].value); !s.ok())
          return with_where(s, where);
    }
  }
  return {};
}

}  // namespace quiver::agents::inline rules::schema
