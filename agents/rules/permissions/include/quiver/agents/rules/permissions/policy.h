#pragma once
/// @file
/// A graph-level permissions policy: an ordered list of rules, each reserving one kind of change
/// on some targets to some agents, like a firewall's. The first rule whose action and target
/// match decides: the change is allowed iff its author is among the rule's agents. A change no
/// rule names gets the policy's default.
///
/// File (JSON):
///   { "default": "allow",                       // or "deny"
///     "rules": [
///       { "action": "write",  "target": "speaking",       "agents": ["speech"] },
///       { "action": "rt",     "target": "person_joint",   "agents": ["person"] },
///       { "action": "create", "target": "*",              "agents": ["*"] } ] }
///
/// Actions and their targets:
///   create, delete  a node type                       ("person")
///   write           an attribute, optionally qualified by the node or edge type it is on:
///                   "speaking", "person.speaking", "person.*", "*"
///   edge            an edge type (inserting or deleting such an edge)
///   rt              the type of the child node whose RT placement (parent, pose) changes
///   lock            the type of a lock scope's root node (claiming, renewing or releasing it)
/// A target "*" matches everything; "type.*" every attribute on that type. Agents are agent
/// names; "*" is every agent.
///
/// The decision depends on the change and the policy only: the types a receiver checks are the
/// ones the delta states (every node op of a delta states its node's type).

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "quiver/graph/symbol.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline rules::permissions {

enum class Action : std::uint8_t { kCreate, kDelete, kWrite, kEdge, kRt, kLock };
const char* to_string(Action a);

struct Rule {
  Action action = Action::kWrite;
  std::string target;               ///< as written ("person.speaking", "*")
  std::vector<std::string> agents;  ///< as written
  // Compiled.
  std::string type;  ///< the qualifier before '.', "*" or "" (write: none given)
  std::string name;  ///< write: the attribute ("*" any); others: the type ("*" any)
  std::vector<std::uint64_t> agent_ids;  ///< fnv1a64 of each name
  bool any_agent = false;
};

class Policy {
 public:
  /// Reads a policy file's text; errors name `where` and the rule at fault.
  static Result<Policy> parse(std::string_view json, const std::string& where);
  static Result<Policy> load(const std::string& path);
  /// A policy that allows everything (no rules, default allow).
  static Policy allow_all();

  /// The index of the rule that decides `action` on (type, name), or -1 (the default decides).
  /// For write: `type` is the node or edge type, `name` the attribute; otherwise `type` is the
  /// node (or edge) type and `name` is unused. Cached per (action, type, name).
  int rule_for(Action action, graph::Symbol type, graph::Symbol name) const;
  /// Ok, or kPermissionDenied naming the agent, the change and the rule.
  Status check(std::uint64_t agent, Action action, graph::Symbol type, graph::Symbol name) const;

  bool default_allow() const { return default_allow_; }
  const std::vector<Rule>& rules() const { return rules_; }
  /// The name of an agent the policy names or was told (learn_name), else its id in hex.
  std::string agent_name(std::uint64_t agent) const;
  /// Lets errors name an agent the rules do not name (e.g. every agent with a certificate).
  void learn_name(const std::string& name);

 private:
  bool default_allow_ = true;
  std::vector<Rule> rules_;
  std::unordered_map<std::uint64_t, std::string> names_;
  mutable std::unordered_map<std::uint64_t, int> cache_;
};

}  // namespace quiver::agents::inline rules::permissions
