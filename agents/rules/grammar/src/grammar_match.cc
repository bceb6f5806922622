// Matching one compiled rule against a transaction's changes: variables bound by the changed
// elements, the rest by walking context edges from bound nodes; negative and effect conditions.

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "grammar_compiled.h"

namespace quiver::agents::inline rules {

using internal::Binding;
using internal::Changes;
using internal::eval;

using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;

namespace {

bool edge_in_pre(const Graph& g, const EdgeKey& e) { return g.has_edge(e.from, e.to, e.type); }

}  // namespace

using internal::Compiled;
using internal::edge_text;

GrammarChecker::Impl::Attempt GrammarChecker::Impl::try_rule(const Graph& gr, const Compiled& r, const Changes& c,
                                                             const std::vector<NodeId>* fixed) const {
  const TypeSystem& types = g.types;
  const int n = static_cast<int>(r.vars.size());
  Attempt best;
  std::vector<NodeId> slot(n);
  std::vector<bool> bound(n, false);
  std::set<NodeId> used;
  auto type_of = [&](NodeId id) -> const std::string& {
    auto it = c.created.find(id);
    return it != c.created.end() ? it->second : gr.type_of(id).str();
  };
  auto note = [&](int progress, std::string why) {
    if (progress > best.progress || best.why.empty()) {
      best.progress = progress;
      best.why = std::move(why);
    }
  };
  auto bind = [&](int s, NodeId id, int progress) -> bool {
    if (bound[s]) {
      if (slot[s] == id) return true;
      note(progress, "variable '" + r.vars[s] + "' would have to be two nodes at once");
      return false;
    }
    if (used.count(id)) {
      note(progress, "two variables would match the same node " + gr.name_of(id) + " (matches are injective)");
      return false;
    }
    if (!types.is_a(type_of(id), r.types[s])) {
      note(progress, "'" + r.vars[s] + "' must be a " + r.types[s] + " but " +
                         (gr.name_of(id).empty() ? id.to_string() : gr.name_of(id)) + " is a " + type_of(id));
      return false;
    }
    bound[s] = true;
    slot[s] = id;
    used.insert(id);
    return true;
  };
  auto unbind = [&](int s) {
    bound[s] = false;
    used.erase(slot[s]);
  };

  // Obligations: each rule change maps to a distinct change of the transaction.
  struct Ob {
    enum { kRemoved, kAdded, kDeleted, kCreated, kRetyped } kind;
    int index;
  };
  std::vector<Ob> obs;
  for (int i = 0; i < static_cast<int>(r.removed.size()); ++i) obs.push_back({Ob::kRemoved, i});
  for (int i = 0; i < static_cast<int>(r.added.size()); ++i) obs.push_back({Ob::kAdded, i});
  for (int i = 0; i < static_cast<int>(r.deleted.size()); ++i) obs.push_back({Ob::kDeleted, i});
  for (int i = 0; i < static_cast<int>(r.created.size()); ++i) obs.push_back({Ob::kCreated, i});
  for (int i = 0; i < static_cast<int>(r.retyped.size()); ++i) obs.push_back({Ob::kRetyped, i});
  std::vector<bool> used_removed(c.removed.size()), used_added(c.added.size());
  std::vector<NodeId> deleted(c.deleted.begin(), c.deleted.end());
  std::vector<NodeId> created, retyped;
  for (const auto& [id, t] : c.created) created.push_back(id);
  for (const auto& [id, t] : c.retyped) retyped.push_back(id);
  std::vector<bool> used_deleted(deleted.size()), used_created(created.size()), used_retyped(retyped.size());

  std::function<bool(std::size_t)> context;  // binds the remaining variables and checks the rest
  std::function<bool(std::size_t)> oblige = [&](std::size_t k) -> bool {
    const int progress = static_cast<int>(k) * 10;
    if (k == obs.size()) return context(0);
    const Ob& ob = obs[k];
    if (ob.kind == Ob::kRemoved || ob.kind == Ob::kAdded) {
      const Compiled::E& e = ob.kind == Ob::kRemoved ? r.removed[ob.index] : r.added[ob.index];
      const auto& pool = ob.kind == Ob::kRemoved ? c.removed : c.added;
      auto& taken = ob.kind == Ob::kRemoved ? used_removed : used_added;
      bool any = false;
      for (std::size_t i = 0; i < pool.size(); ++i) {
        if (taken[i] || pool[i].type != e.label) continue;
        any = true;
        bool fb = bound[e.from], tb = bound[e.to];
        if (!bind(e.from, pool[i].from, progress)) continue;
        if (!bind(e.to, pool[i].to, progress)) {
          if (!fb) unbind(e.from);
          continue;
        }
        taken[i] = true;
        if (oblige(k + 1)) return true;
        taken[i] = false;
        if (!tb) unbind(e.to);
        if (!fb) unbind(e.from);
      }
      if (!any)
        note(progress, std::string("it ") + (ob.kind == Ob::kRemoved ? "removes" : "adds") +
                           " an edge (" + e.label.str() + ") " + r.vars[e.from] + "->" +
                           r.vars[e.to] + " that this change does not");
      return false;
    }
    const bool del = ob.kind == Ob::kDeleted, ret = ob.kind == Ob::kRetyped;
    const int s = del ? r.deleted[ob.index] : ret ? r.retyped[ob.index] : r.created[ob.index];
    auto& pool = del ? deleted : ret ? retyped : created;
    auto& taken = del ? used_deleted : ret ? used_retyped : used_created;
    bool any = false;
    for (std::size_t i = 0; i < pool.size(); ++i) {
      if (taken[i]) continue;
      if (ret && !types.is_a(c.retyped.at(pool[i]), r.retype_to[ob.index])) {
        note(progress, "it retypes '" + r.vars[s] + "' to " + r.retype_to[ob.index] + ", but the change makes " +
                           gr.name_of(pool[i]) + " a " + c.retyped.at(pool[i]));
        continue;
      }
      any = true;
      bool was = bound[s];
      if (!bind(s, pool[i], progress)) continue;
      taken[i] = true;
      if (oblige(k + 1)) return true;
      taken[i] = false;
      if (!was) unbind(s);
    }
    if (!any && !ret)
      note(progress, std::string("it ") + (del ? "deletes" : "creates") + " a " + r.types[s] + " ('" + r.vars[s] +
                         "') that this change does not");
    if (!any && ret && pool.empty())
      note(progress, "it retypes '" + r.vars[s] + "' (a " + r.types[s] + ") to " + r.retype_to[ob.index] +
                         ", which this change does not");
    return false;
  };

  context = [&](std::size_t) -> bool {
    const int progress = static_cast<int>(obs.size()) * 10 + 5;
    // Bind unbound (kept) variables by walking context edges from bound ones.
    int pick = -1;
    const Compiled::E* via = nullptr;
    for (const auto& e : r.context) {
      if (bound[e.from] != bound[e.to]) {
        pick = bound[e.from] ? e.to : e.from;
        via = &e;
        break;
      }
    }
    if (pick < 0)
      for (int s = 0; s < n; ++s)
        if (!bound[s]) {
          pick = s;
          break;
        }
    if (pick >= 0) {
      std::vector<NodeId> cand;
      if (via && via->label == graph::symbols::rt()) {
        if (via->to == pick)
          cand = gr.rt_children(slot[via->from]);
        else if (auto p = gr.rt_parent(slot[via->to]))
          cand.push_back(*p);
      } else if (via) {
        if (via->to == pick)
          for (const EdgeKey& k : gr.edges_from(slot[via->from], via->label)) cand.push_back(k.to);
        else
          for (const EdgeKey& k : gr.edges_to(slot[via->to], via->label)) cand.push_back(k.from);
      } else {
        cand = gr.nodes();  // a context variable no edge reaches: scan
      }
      bool any = false;
      for (NodeId id : cand) {
        if (c.deleted.count(id) || c.created.count(id)) continue;
        if (!bind(pick, id, progress)) continue;
        any = true;
        if (context(0)) return true;
        unbind(pick);
      }
      if (!any)
        note(progress, via ? "it needs an edge " + edge_text(r, *via) + " that the graph lacks"
                           : "no node can play '" + r.vars[pick] + "' (a " + r.types[pick] + ")");
      return false;
    }
    // Everything bound: context edges present (and kept), negatives absent, precondition true.
    auto ref = [&](const Compiled::E& e) { return EdgeKey{slot[e.from], slot[e.to], e.label}; };
    auto removed_now = [&](const EdgeKey& e) {
      return std::find(c.removed.begin(), c.removed.end(), e) != c.removed.end();
    };
    auto added_now = [&](const EdgeKey& e) {
      return std::find(c.added.begin(), c.added.end(), e) != c.added.end();
    };
    for (const auto& e : r.context) {
      EdgeKey x = ref(e);
      bool endpoint_deleted = c.deleted.count(x.from) || c.deleted.count(x.to);
      if (!edge_in_pre(gr, x) || (!endpoint_deleted && removed_now(x))) {
        note(progress + 1, "it needs an edge " + edge_text(r, e) + " that the graph lacks");
        return false;
      }
    }
    for (const auto& e : r.neg_pre)
      if (edge_in_pre(gr, ref(e))) {
        note(progress + 2, "it forbids the edge " + edge_text(r, e) + ", which exists");
        return false;
      }
    for (const auto& e : r.neg_post) {
      EdgeKey x = ref(e);
      if ((edge_in_pre(gr, x) && !removed_now(x)) || added_now(x)) {
        note(progress + 2, "its result forbids the edge " + edge_text(r, e));
        return false;
      }
    }
    Binding b;
    for (int s = 0; s < n; ++s) b[r.vars[s]] = slot[s];
    if (r.rule->precondition && !eval(gr, types, *r.rule->precondition, b)) {
      note(progress + 3, "its precondition does not hold");
      return false;
    }
    if (r.effect) {
      // The rewrite, then the effect over its outcome: together exactly the change.
      internal::Outcome out;
      for (const auto& e : r.removed) out.edges[ref(e)] = false;
      for (const auto& e : r.added) out.edges[ref(e)] = true;
      for (int s : r.deleted) out.deleted.insert(slot[s]);
      for (int s : r.created) out.created[slot[s]] = c.created.at(slot[s]);
      for (int s : r.retyped) out.retyped[slot[s]] = c.retyped.at(slot[s]);
      internal::apply_effect(gr, types, *r.effect, b, out);
      std::string why;
      if (!internal::outcome_is(gr, types, out, c, why)) {
        note(progress + 4, (r.rule->foralls.empty() ? "with its effect, " : "with its forall effects, ") + why);
        return false;
      }
    } else {
      auto same = [&](const std::vector<Compiled::E>& want, std::vector<EdgeKey> have) {
        if (want.size() != have.size()) return false;
        std::vector<EdgeKey> w;
        for (const auto& e : want) w.push_back(ref(e));
        std::sort(w.begin(), w.end(), graph::canonical_less);
        std::sort(have.begin(), have.end(), graph::canonical_less);
        return w == have;
      };
      if (!same(r.removed, c.removed) || !same(r.added, c.added)) {
        note(progress + 4, "the change does more than the rule");
        return false;
      }
      if (r.deleted.size() != c.deleted.size() || r.created.size() != c.created.size() ||
          r.retyped.size() != c.retyped.size()) {
        note(progress + 4, "the change creates, deletes or retypes other nodes than the rule");
        return false;
      }
    }
    best.ok = true;
    best.slots = slot;
    return true;
  };

  if (fixed) {
    // Verification of a claimed binding: pre-bind every variable, then run the same checks.
    for (int s = 0; s < n; ++s)
      if (!bind(s, (*fixed)[s], 0)) return best;
  }
  oblige(0);
  return best;
}

}  // namespace quiver::agents
