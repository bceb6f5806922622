// A grammar run on one agent: local transactions checked before they are published, incoming deltas verified
// against their origin's grammar, constraints checked after merges and violations repaired.
#include "quiver/agents/rules/grammar/grammar_guard.h"

#include <algorithm>

namespace quiver::agents::inline rules {

using graph::NodeId;

GrammarGuard::GrammarGuard(graph::Graph& g, GrammarChecker checker, std::string agent_name)
    : g_(g), checker_(std::move(checker)), name_(std::move(agent_name)) {
  for (const Constraint& c : checker_.grammar().constraints) where_free_ = where_free_ && !c.where;
  // Starting from a graph without violations, on_changes keeps every violation in open_.
  complete_ = where_free_ && (g_.node_count() == 0 || checker_.all_violations(g_).empty());
  sub_ = g_.subscribe([this](const graph::ChangeBatch& b) { on_changes(b); });
  merge_observer_ = g_.add_merge_observer([this](const graph::Graph& before, const graph::GraphDelta& d) {
    if (d.kind != graph::GraphDelta::Kind::kDelta) return;  // states carry no single rule
    auto peer = peers_.find(d.origin.agent);
    Status s = (peer == peers_.end() ? checker_ : peer->second).verify_delta(before, d);
    if (s.ok()) {
      if (!d.rule.empty()) ++verified_;
      return;
    }
    ++unverified_;
    if (unverified_cb_) unverified_cb_(d.origin, s.error());
  });
}

GrammarGuard::~GrammarGuard() {
  g_.unsubscribe(sub_);
  g_.remove_merge_observer(merge_observer_);
}

graph::Graph::CommitValidator GrammarGuard::validator() {
  return [this](const graph::Graph& g, const std::vector<graph::TxnOp>& ops) -> Status {
    if (repairing_) return g_.annotate_commit("repair", {});  // the documented exception: receivers know it is one
    RuleMatch m;
    Status s = checker_.check(g, ops, &m);
    if (s.ok() && !m.rule.empty()) return g_.annotate_commit(std::move(m.rule), std::move(m.binding));
    return s;
  };
}

void GrammarGuard::verify_with(std::uint64_t agent_id, GrammarChecker checker) {
  peers_.insert_or_assign(agent_id, std::move(checker));
}

void GrammarGuard::install() { g_.set_commit_validator(validator()); }

void GrammarGuard::on_changes(const graph::ChangeBatch& b) {
  if (checker_.grammar().constraints.empty()) return;
  // anchors: the nodes around which violations may have appeared; changed: the nodes that
  // appeared or disappeared or whose edges did (attribute and pose updates change none).
  std::vector<NodeId> anchors, changed;
  for (const auto& n : b.nodes) {
    if (n.kind != graph::ChangeKind::kDeleted) anchors.push_back(n.id);
    if (n.kind != graph::ChangeKind::kUpdated) changed.push_back(n.id);
  }
  for (const auto& e : b.edges) {
    anchors.push_back(e.key.from);
    anchors.push_back(e.key.to);
    if (e.kind == graph::ChangeKind::kUpdated) continue;
    changed.push_back(e.key.from);
    changed.push_back(e.key.to);
  }
  // Without 'where' conditions, whether a binding violates a constraint depends only on which of
  // its nodes exist and the edges among them. So a violation none of whose nodes changed still
  // holds, and once open_ holds every violation (complete_), a batch that changes no node or
  // edge can neither close nor open one.
  if (complete_ && changed.empty()) return;
  std::sort(anchors.begin(), anchors.end());
  anchors.erase(std::unique(anchors.begin(), anchors.end()), anchors.end());
  std::sort(changed.begin(), changed.end());
  auto unchanged = [&](const OpenViolation& o) {
    for (const auto& [var, id] : o.second)
      if (std::binary_search(changed.begin(), changed.end(), id)) return false;
    return true;
  };
  // Violations that no longer hold are closed; new ones are reported.
  for (auto it = open_.begin(); it != open_.end();) {
    if (where_free_ && unchanged(*it)) {
      ++it;
      continue;
    }
    const bool still = checker_.still_violated(g_, Violation{it->first, it->second});
    it = still ? std::next(it) : open_.erase(it);
  }
  for (const Violation& v : checker_.violations_around(g_, anchors)) {
    if (!open_.emplace(v.constraint, v.binding).second) continue;
    ++seen_;
    if (cb_) cb_(v);
    for (const Constraint& c : checker_.grammar().constraints)
      if (c.name == v.constraint && c.repair_agent == name_) to_repair_.push_back(v);
  }
}

void GrammarGuard::tick() {
  // Library code never commits inside a caller's transaction: repairs wait for the next tick.
  if (g_.transaction_open()) return;
  std::vector<Violation> work;
  work.swap(to_repair_);
  for (const Violation& v : work) {
    const Constraint* con = nullptr;
    for (const Constraint& c : checker_.grammar().constraints)
      if (c.name == v.constraint) con = &c;
    if (!con) continue;
    // Still there? Then delete the oldest edge of the match.
    if (!checker_.still_violated(g_, v)) continue;
    auto at = [&](const std::string& var) {
      for (const auto& [x, id] : v.binding)
        if (x == var) return id;
      return NodeId{};
    };
    std::optional<graph::EdgeKey> oldest;
    graph::Dot oldest_version;
    for (const PatternEdge& e : con->forbid.edges) {
      if (e.negated) continue;
      graph::EdgeKey k{at(e.from), at(e.to), e.symbol};
      auto ver = g_.edge_version(k);
      if (ver && (!oldest || crdt::lamport_less(*ver, oldest_version))) {
        oldest = k;
        oldest_version = *ver;
      }
    }
    if (!oldest) continue;
    repairing_ = true;
    auto tx = g_.begin();
    if (tx.delete_edge(oldest->from, oldest->to, oldest->type).ok() && tx.commit().ok()) ++repairs_;
    repairing_ = false;
  }
}

}  // namespace quiver::agents
