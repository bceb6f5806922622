// A rule's effect applied to the outcome of its rewrite, and that outcome compared with what a change did.
#include "grammar_effect.h"

#include <algorithm>

namespace quiver::agents::inline rules::internal {

using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;

bool Outcome::alive(const Graph& before, NodeId n) const {
  if (deleted.count(n)) return false;
  return created.count(n) != 0 || before.has_node(n);
}

std::string Outcome::type_of(const Graph& before, NodeId n) const {
  if (auto it = created.find(n); it != created.end()) return it->second;
  if (auto it = retyped.find(n); it != retyped.end()) return it->second;
  return before.type_of(n).str();
}

namespace {

// Stand-in ids of the nodes an effect creates; no replica mints them.
NodeId placeholder(std::size_t i) {
  return NodeId{graph::Dot{graph::ReplicaId{~0ULL, ~0ULL}, static_cast<std::uint64_t>(i + 1)}};
}
bool is_placeholder(NodeId n) { return n.dot.replica == graph::ReplicaId{~0ULL, ~0ULL}; }

struct Anchor {
  const PatternEdge* edge;
  bool written;  // also look at edges the outcome adds (a removal may undo the rewrite's own)
};

// Edges that any node `var` must have, for `body` to do anything to it: the nodes they reach
// from bound ones are the only candidates. False if there are none (`body` may act on any node
// of the type: scan).
bool anchors_of(const Effect& body, const std::string& var, const Binding& b,
                std::vector<Anchor>& out) {
  auto usable = [&](const PatternEdge& e) {
    if (e.from == e.to) return false;
    if (e.to == var) return b.count(e.from) != 0;
    if (e.from == var) return b.count(e.to) != 0;
    return false;
  };
  switch (body.kind) {
    case Effect::Kind::kWhen: {
      std::vector<const PatternEdge*> edges;
      collect_edges(body.condition, edges);
      for (const PatternEdge* e : edges)
        if (usable(*e)) {
          out.push_back({e, false});
          return true;
        }
      return anchors_of(body.kids[0], var, b, out);
    }
    case Effect::Kind::kRemoveEdge:
      if (!usable(body.edge)) return false;
      out.push_back({&body.edge, true});
      return true;
    case Effect::Kind::kAll:
      for (const Effect& k : body.kids)
        if (!anchors_of(k, var, b, out)) return false;
      return true;
    default:
      return false;
  }
}

std::vector<NodeId> effect_candidates(const Graph& before, const TypeSystem& types,
                                      const PatternNode& v, const Effect& body, const Binding& b,
                                      const Outcome& out) {
  std::vector<NodeId> cand;
  std::vector<Anchor> anchors;
  if (anchors_of(body, v.var, b, anchors)) {
    for (const Anchor& a : anchors) {
      const bool forward = a.edge->to == v.var;
      const NodeId other = b.at(forward ? a.edge->from : a.edge->to);
      if (forward)
        for (const EdgeKey& k : before.edges_from(other, a.edge->symbol)) cand.push_back(k.to);
      else
        for (const EdgeKey& k : before.edges_to(other, a.edge->symbol)) cand.push_back(k.from);
      if (!a.written) continue;
      for (const auto& [k, present] : out.edges)
        if (present && k.type == a.edge->symbol && (forward ? k.from == other : k.to == other))
          cand.push_back(forward ? k.to : k.from);
    }
  } else {
    // Every node of the type, after the rewrite (documented cost).
    for (const std::string& t : types.subtypes(v.type))
      for (NodeId n : before.nodes_of_type(graph::Symbol::find(t))) cand.push_back(n);
    for (const auto& [n, t] : out.created) cand.push_back(n);
    for (const auto& [n, t] : out.retyped) cand.push_back(n);
  }
  std::sort(cand.begin(), cand.end());
  cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  std::vector<NodeId> typed;
  for (NodeId n : cand)
    if (out.alive(before, n) && types.is_a(out.type_of(before, n), v.type)) typed.push_back(n);
  return typed;
}

void apply(const Graph& before, const TypeSystem& types, const Effect& e, Binding& b, Outcome& out);

void forall(const Graph& before, const TypeSystem& types, const Effect& e, std::size_t i,
            Binding& b, Outcome& out) {
  if (i == e.vars.size()) {
    apply(before, types, e.kids[0], b, out);
    return;
  }
  const PatternNode& v = e.vars[i];
  std::optional<NodeId> outer;  // a quantified variable may shadow a bound one
  if (auto it = b.find(v.var); it != b.end()) {
    outer = it->second;
    b.erase(it);
  }
  for (NodeId n : effect_candidates(before, types, v, e.kids[0], b, out)) {
    if (e.distinct) {
      bool used = false;
      for (const auto& [name, m] : b) used = used || m == n;
      if (used) continue;
    }
    b[v.var] = n;
    forall(before, types, e, i + 1, b, out);
    b.erase(v.var);
  }
  if (outer) b[v.var] = *outer;
}

void apply(const Graph& before, const TypeSystem& types, const Effect& e, Binding& b,
           Outcome& out) {
  switch (e.kind) {
    case Effect::Kind::kAll:
      for (const Effect& k : e.kids) apply(before, types, k, b, out);
      return;
    case Effect::Kind::kWhen:
      if (eval(before, types, e.condition, b)) {
        Binding inner = b;  // what the body creates is its own
        apply(before, types, e.kids[0], inner, out);
      }
      return;
    case Effect::Kind::kForall: {
      Binding inner = b;
      forall(before, types, e, 0, inner, out);
      return;
    }
    case Effect::Kind::kAddEdge:
    case Effect::Kind::kRemoveEdge: {
      const NodeId from = b.at(e.edge.from), to = b.at(e.edge.to);
      if (!out.alive(before, from) || !out.alive(before, to)) return;
      out.edges[EdgeKey{from, to, e.edge.symbol}] = e.kind == Effect::Kind::kAddEdge;
      return;
    }
    case Effect::Kind::kCreate: {
      const NodeId id = placeholder(out.placeholders.size());
      out.placeholders.push_back(id);
      out.created[id] = e.type;
      b[e.var] = id;
      return;
    }
    case Effect::Kind::kDelete: {
      const NodeId id = b.at(e.var);
      if (out.created.erase(id) == 0) out.deleted.insert(id);
      out.retyped.erase(id);
      return;
    }
    case Effect::Kind::kRetype: {
      const NodeId id = b.at(e.var);
      if (!out.alive(before, id)) return;
      if (auto it = out.created.find(id); it != out.created.end())
        it->second = e.type;
      else
        out.retyped[id] = e.type;
      return;
    }
  }
}

using EdgeList = std::vector<EdgeKey>;

EdgeList sorted(EdgeList v) {
  std::sort(v.begin(), v.end(), graph::canonical_less);
  return v;
}

}  // namespace

void apply_effect(const Graph& before, const TypeSystem& types, const Effect& e, Binding& b,
                  Outcome& out) {
  apply(before, types, e, b, out);
}

bool outcome_is(const Graph& before, const TypeSystem& types, const Outcome& out, const Changes& c,
                std::string& why) {
  // Nodes deleted and retyped.
  std::set<NodeId> deleted;
  for (NodeId n : out.deleted)
    if (before.has_node(n)) deleted.insert(n);
  if (deleted != c.deleted) {
    why = "the change deletes other nodes than the rule and its effect";
    return false;
  }
  std::map<NodeId, std::string> retyped;
  for (const auto& [n, t] : out.retyped)
    if (out.alive(before, n) && t != before.type_of(n).str()) retyped[n] = t;
  bool same_retypes = retyped.size() == c.retyped.size();
  for (const auto& [n, t] : retyped) {
    auto it = c.retyped.find(n);
    same_retypes = same_retypes && it != c.retyped.end() && types.is_a(it->second, t);
  }
  if (!same_retypes) {
    why = "the change retypes other nodes than the rule and its effect";
    return false;
  }
  // Nodes created: the rewrite's are the change's own ids; an effect's are matched below.
  std::vector<NodeId> holders, free;
  for (const auto& [n, t] : out.created) {
    if (is_placeholder(n))
      holders.push_back(n);
    else if (!c.created.count(n)) {
      why = "the change does not create a node the rule creates";
      return false;
    }
  }
  for (const auto& [n, t] : c.created)
    if (!out.created.count(n)) free.push_back(n);
  if (holders.size() != free.size()) {
    why = "the change creates " + std::to_string(free.size()) +
          " node(s) where the effect creates " + std::to_string(holders.size());
    return false;
  }
  // Edges written whose value differs from the state before.
  EdgeList add, remove;
  for (const auto& [k, present] : out.edges) {
    if (!out.alive(before, k.from) || !out.alive(before, k.to)) continue;
    const bool pre = before.has_edge(k.from, k.to, k.type);
    if (present && !pre) add.push_back(k);
    if (!present && pre) remove.push_back(k);
  }
  if (sorted(remove) != sorted(c.removed)) {
    why = "the change removes other edges than the rule and its effect";
    return false;
  }
  const EdgeList want_added = sorted(c.added);
  // Match the effect's new nodes to the change's: by type, then by the edges they get.
  std::map<NodeId, NodeId> as;
  std::vector<bool> taken(free.size());
  std::function<bool(std::size_t)> match = [&](std::size_t i) -> bool {
    if (i == holders.size()) {
      EdgeList got;
      for (EdgeKey k : add) {
        if (auto it = as.find(k.from); it != as.end()) k.from = it->second;
        if (auto it = as.find(k.to); it != as.end()) k.to = it->second;
        got.push_back(k);
      }
      return sorted(std::move(got)) == want_added;
    }
    for (std::size_t j = 0; j < free.size(); ++j) {
      if (taken[j] || !types.is_a(c.created.at(free[j]), out.created.at(holders[i]))) continue;
      taken[j] = true;
      as[holders[i]] = free[j];
      if (match(i + 1)) return true;
      taken[j] = false;
    }
    return false;
  };
  if (!match(0)) {
    why = holders.empty() ? "the change adds other edges than the rule and its effect"
                          : "the change's new nodes and edges are not the ones the effect creates";
    return false;
  }
  return true;
}

}  // namespace quiver::agents::inline rules::internal
