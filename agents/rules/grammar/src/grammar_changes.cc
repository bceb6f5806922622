// The structural changes a transaction or an incoming delta makes to the state it starts from, with a node deleted
// and one created under its name read as one retyped node.
#include "grammar_changes.h"

#include <algorithm>

namespace quiver::agents::inline rules::internal {

using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;
using graph::Symbol;
using graph::TxnOp;

namespace {

// Edges of a change are graph::EdgeKey, ordered by graph::canonical_less (types by text, not by
// symbol index, which depends on interning order).
using EdgeMap = std::map<EdgeKey, bool, decltype(&graph::canonical_less)>;

bool edge_in_pre(const Graph& g, const EdgeKey& e) { return g.has_edge(e.from, e.to, e.type); }

// System attributes ("__lock", ...) belong to the runtime, not to the domain grammar.
bool system_attr(Symbol a) { return a.str().rfind("__", 0) == 0; }

// The graph cannot change a node's type: an agent retypes a node by deleting it and creating a
// node of the new type under the same name, with its edges, in one change. Read such a pair as
// one retyped node (the old id): edges re-created on the new node are no change, the old node's
// edges left behind are removed, the new node's other edges are added.
void read_replacements_as_retypes(const Grammar& gr, const Graph& g,
                                  const std::map<NodeId, std::string>& names, Changes& c) {
  if (c.deleted.empty() || c.created.empty()) return;
  std::map<NodeId, NodeId> replaced;  // new id -> old id
  for (NodeId old : c.deleted) {
    const std::string name = g.name_of(old);
    for (const auto& [id, n] : names)
      if (n == name && c.created.count(id) && !replaced.count(id)) {
        replaced[id] = old;
        break;
      }
  }
  if (replaced.empty()) return;
  auto as_old = [&](NodeId n) {
    auto it = replaced.find(n);
    return it == replaced.end() ? n : it->second;
  };
  for (const auto& [fresh, old] : replaced) {
    c.retyped[old] = c.created.at(fresh);
    c.created.erase(fresh);
    c.deleted.erase(old);
  }
  // The old nodes' edges before the change (an edge between two of them, once).
  EdgeMap before(graph::canonical_less);
  const Symbol rt = graph::symbols::rt();
  for (const auto& [fresh, old] : replaced) {
    for (const EdgeKey& e : g.edges_from(old)) before.emplace(e, false);
    for (const EdgeKey& e : g.edges_to(old)) before.emplace(e, false);
  }
  std::vector<EdgeKey> added;
  for (EdgeKey e : c.added) {
    e.from = as_old(e.from);
    e.to = as_old(e.to);
    if (auto it = before.find(e); it != before.end())
      it->second = true;  // kept
    else
      added.push_back(e);
  }
  c.added = std::move(added);
  for (const auto& [e, kept] : before) {
    if (kept || (gr.allow_rt_moves && e.type == rt)) continue;
    if (c.deleted.count(e.from) || c.deleted.count(e.to)) continue;  // goes with its other node
    c.removed.push_back(e);
  }
}

}  // namespace

Changes extract(const Grammar& gr, const Graph& g, const std::vector<TxnOp>& ops) {
  Changes c;
  std::map<NodeId, std::string> names;                // created node -> name
  EdgeMap state(graph::canonical_less);               // edge -> present after the ops so far
  std::map<NodeId, std::optional<NodeId>> rt_parent;  // child -> parent after the ops so far
  auto present = [&](const EdgeKey& e) {
    auto it = state.find(e);
    return it != state.end() ? it->second : edge_in_pre(g, e);
  };
  auto parent_of = [&](NodeId child) -> std::optional<NodeId> {
    auto it = rt_parent.find(child);
    return it != rt_parent.end() ? it->second : g.rt_parent(child);
  };
  const Symbol rt = graph::symbols::rt();
  for (const TxnOp& op : ops) {
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode:
        c.created[op.node] = op.type.str();
        names[op.node] = op.name;
        break;
      case TxnOp::Kind::kDeleteNode:
        if (c.created.erase(op.node) == 0) c.deleted.insert(op.node);
        break;
      case TxnOp::Kind::kSetAttr:
      case TxnOp::Kind::kRemoveAttr:
        c.need(gr.allow_attributes || system_attr(op.attr) || c.created.count(op.node), [&] {
          return "attribute '" + op.attr.str() + "' of " + g.name_of(op.node) +
                 " changes but the grammar has no 'allow attributes'";
        });
        break;
      case TxnOp::Kind::kInsertEdge: {
        EdgeKey e{op.node, op.other, op.type};
        c.need(gr.allow_attributes || op.attrs.empty() || !present(e), [] {
          return std::string("edge attributes change but the grammar has no 'allow attributes'");
        });
        state[e] = true;
        break;
      }
      case TxnOp::Kind::kDeleteEdge:
        state[EdgeKey{op.node, op.other, op.type}] = false;
        break;
      case TxnOp::Kind::kSetEdgeAttr:
      case TxnOp::Kind::kRemoveEdgeAttr:
        c.need(gr.allow_attributes || !edge_in_pre(g, EdgeKey{op.node, op.other, op.type}), [&] {
          return "edge attribute '" + op.attr.str() +
                 "' changes but the grammar has no 'allow attributes'";
        });
        break;
      case TxnOp::Kind::kSetRt: {
        auto old = parent_of(op.node);
        if (old && *old == op.other) {
          c.need(gr.allow_rt_poses || c.created.count(op.node), [&] {
            return "the RT pose of " + g.name_of(op.node) +
                   " changes but the grammar has no 'allow rt-poses'";
          });
          break;
        }
        rt_parent[op.node] = op.other;
        if (gr.allow_rt_moves) break;
        if (old) state[EdgeKey{*old, op.node, rt}] = false;
        state[EdgeKey{op.other, op.node, rt}] = true;
        break;
      }
      case TxnOp::Kind::kRemoveRt: {
        auto old = parent_of(op.node);
        rt_parent[op.node] = std::nullopt;
        if (old && !gr.allow_rt_moves) state[EdgeKey{*old, op.node, rt}] = false;
        break;
      }
    }
  }
  for (const auto& [e, now] : state) {
    if (c.deleted.count(e.from) || c.deleted.count(e.to)) continue;  // goes with its node
    bool pre = edge_in_pre(g, e);
    if (now && !pre) c.added.push_back(e);
    if (!now && pre) c.removed.push_back(e);
  }
  read_replacements_as_retypes(gr, g, names, c);
  return c;
}

Changes extract_delta(const Grammar& gr, const Graph& g, const graph::GraphDelta& d) {
  Changes c;
  std::map<NodeId, std::string> names;
  const Symbol rt = graph::symbols::rt();
  for (const auto& n : d.nodes) {
    if (n.has_header && !g.has_node(n.id) && !g.context().contains(n.id.dot)) {
      c.created[n.id] = n.type.str();
      names[n.id] = n.name;
    }
    if (n.removed && g.has_node(n.id)) c.deleted.insert(n.id);
  }
  for (const auto& n : d.nodes) {
    const bool fresh = c.created.count(n.id) != 0;
    if (!gr.allow_attributes && !fresh && !n.removed)
      for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i)
        c.need(system_attr(d.attrs[i].name), [&] {
          return "attribute '" + d.attrs[i].name.str() +
                 "' changes but the grammar has no 'allow attributes'";
        });
    const auto old = g.rt_parent(n.id);
    for (std::uint32_t i = n.claim_added.begin; i < n.claim_added.end; ++i) {
      const graph::RtClaim& cl = d.claims[i].value;
      if (old && !cl.parent.is_null() && *old == cl.parent) continue;
      if (gr.allow_rt_moves) continue;
      if (old) c.removed.push_back(EdgeKey{*old, n.id, rt});
      if (!cl.parent.is_null()) c.added.push_back(EdgeKey{cl.parent, n.id, rt});
    }
    c.need(gr.allow_rt_poses || n.samples.empty() || fresh, [] {
      return std::string("an RT pose changes but the grammar has no 'allow rt-poses'");
    });
  }
  for (const auto& e : d.edges) {
    if (c.deleted.count(e.key.from) || c.deleted.count(e.key.to)) continue;
    const bool pre = g.has_edge(e.key.from, e.key.to, e.key.type);
    EdgeKey ref{e.key.from, e.key.to, e.key.type};
    if (!pre && !e.added.empty())
      c.added.push_back(ref);
    else if (pre && e.added.empty() && !e.removed.empty())
      c.removed.push_back(ref);
    else if (pre && !gr.allow_attributes) {
      for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i)
        c.need(d.attrs[i].added.empty(), [] {
          return std::string("edge attributes change but the grammar has no 'allow attributes'");
        });
    }
  }
  read_replacements_as_retypes(gr, g, names, c);
  return c;
}

std::string describe(const Graph& g, const EdgeKey& e,
                     const std::map<NodeId, std::string>& created) {
  auto name = [&](NodeId n) {
    std::string s = g.name_of(n);
    if (s.empty()) s = created.count(n) ? "new " + created.at(n) : n.to_string();
    return s;
  };
  return name(e.from) + " -[" + e.type.str() + "]-> " + name(e.to);
}

std::string describe(const Graph& g, const Changes& c) {
  std::string s;
  auto add = [&](const std::string& x) { s += (s.empty() ? "" : ", ") + x; };
  for (const auto& [id, type] : c.created) add("create a " + type);
  for (NodeId n : c.deleted) add("delete " + g.name_of(n));
  for (const auto& [id, type] : c.retyped)
    add("retype " + g.name_of(id) + " (a " + g.type_of(id).str() + ") to " + type);
  for (const auto& e : c.removed) add("remove " + describe(g, e, c.created));
  for (const auto& e : c.added) add("add " + describe(g, e, c.created));
  return s;
}

}  // namespace quiver::agents::inline rules::internal
