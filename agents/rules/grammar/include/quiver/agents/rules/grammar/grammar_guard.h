#pragma once
/// @file
/// Runs a grammar on one agent: every local transaction is checked before it is published, and
/// after every merge the constraints are checked around what changed. A violation raises an
/// event (the same violation on every replica that holds the same state); the agent the grammar
/// names for the constraint repairs it by its policy ("delete oldest": remove the oldest edge of
/// the forbidden match, by Lamport order of its insertion - a deterministic choice).

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules {

class GrammarGuard {
 public:
  /// `agent_name` decides which constraints this agent repairs.
  GrammarGuard(graph::Graph& g, GrammarChecker checker, std::string agent_name);
  ~GrammarGuard();
  GrammarGuard(const GrammarGuard&) = delete;
  GrammarGuard& operator=(const GrammarGuard&) = delete;

  /// The commit check, for Graph::set_commit_validator (or to chain with locks).
  graph::Graph::CommitValidator validator();
  /// Installs validator() on the graph.
  void install();
  /// Performs pending repairs (outside of merge callbacks). Call periodically.
  void tick();

  /// Deltas from the agent with this id (its name's hash: ReplicaId::agent) are verified against
  /// `checker`, that agent's own grammar; deltas from agents without one, against this agent's.
  void verify_with(std::uint64_t agent_id, GrammarChecker checker);
  void on_violation(std::function<void(const Violation&)> cb) { cb_ = std::move(cb); }
  /// Called for every incoming delta whose claimed rule does not verify (or whose structural
  /// change claims none): the origin and why. The delta is still merged (replicas converge);
  /// what to do about its sender is the application's call.
  void on_unverified(std::function<void(const graph::ReplicaId&, const Error&)> cb) { unverified_cb_ = std::move(cb); }
  std::uint64_t deltas_verified() const { return verified_; }
  std::uint64_t deltas_unverified() const { return unverified_; }
  /// An open violation: its constraint and binding.
  using OpenViolation = std::pair<std::string, std::vector<std::pair<std::string, graph::NodeId>>>;
  /// Violations currently present around what changed since start (re-checked when it changes).
  const std::set<OpenViolation>& open() const { return open_; }
  std::uint64_t violations_seen() const { return seen_; }
  std::uint64_t repairs_made() const { return repairs_; }
  const GrammarChecker& checker() const { return checker_; }

 private:
  void on_changes(const graph::ChangeBatch& b);

  graph::Graph& g_;
  GrammarChecker checker_;
  std::map<std::uint64_t, GrammarChecker> peers_;
  std::string name_;
  graph::Graph::SubscriptionId sub_ = 0;
  graph::Graph::ObserverId merge_observer_ = 0;
  std::function<void(const Violation&)> cb_;
  std::function<void(const graph::ReplicaId&, const Error&)> unverified_cb_;
  std::uint64_t verified_ = 0, unverified_ = 0;
  bool where_free_ =
      true;                // no constraint has a 'where': violations depend on nodes and edges only
  bool complete_ = false;  // where_free_, and open_ holds every violation in the graph
  std::set<OpenViolation> open_;
  std::vector<Violation> to_repair_;
  bool repairing_ = false;
  std::uint64_t seen_ = 0, repairs_ = 0;
};

}  // namespace quiver::agents
