#pragma once
/// @file
/// Graph grammars in the spirit of AGM's AGGL, checked locally by every agent (no executive).
///
/// A grammar file (docs/grammar.md):
///
///     grammar speech
///     types { robot  speaking  test  test_part  object  mug : object }
///     allow attributes            # attribute writes need no rule
///     allow rt-poses              # RT pose updates need no rule
///     rule startSpeaking : active {
///       { r:robot s:speaking t:test tp:test_part  r->s(is_not)  t->tp(is_in) }
///       =>
///       { r:robot s:speaking t:test tp:test_part  r->s(is)      t->tp(is_in) }
///       precondition { tp.label != "" }
///     }
///     constraint robotInOneRoom {
///       forbid { r:robot a:room b:room  r->a(in)  r->b(in) }
///       repair by navigator: delete oldest
///     }
///
/// LHS-only nodes are deleted, RHS-only nodes created, and likewise for edges; `!a->b(l)` is a
/// negative edge (must not exist). A transaction is valid when its structural changes are exactly
/// ONE rule application (typed, injective match, negative edges respected, precondition true,
/// forall effects applied to every match) and its other changes are allowed by `allow` lines.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/result.h"

namespace quiver::agents {

struct SourceLoc {
  int line = 0;
  int column = 0;
};

/// Node types with single inheritance.
class TypeSystem {
 public:
  /// Declares `type` (optionally as a subtype of `base`, which must already exist).
  void declare(const std::string& type, const std::string& base = {});
  bool known(std::string_view type) const { return parent_.find(type) != parent_.end(); }
  /// True if `type` is `base` or inherits from it.
  bool is_a(std::string_view type, std::string_view base) const;

 private:
  // Looked up by string_view (no temporary strings on the check path).
  struct TextHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  std::unordered_map<std::string, std::string, TextHash, std::equal_to<>> parent_;
};

struct PatternNode {
  std::string var;
  std::string type;
  SourceLoc loc;
};

struct PatternEdge {
  std::string from, to, label;
  bool negated = false;
  SourceLoc loc;
  graph::Symbol symbol;  ///< `label`, interned (by the parser; GrammarChecker re-interns its copy)
};

struct Pattern {
  std::vector<PatternNode> nodes;
  std::vector<PatternEdge> edges;
  const PatternNode* node(std::string_view var) const;
};

enum class CompareOp : std::uint8_t { kEq, kNe, kLt, kLe, kGt, kGe };

/// A formula over the graph at a match: and / or / not, edges, attribute comparisons,
/// exists / forall over extra node variables.
struct Formula {
  enum class Kind : std::uint8_t { kTrue, kFalse, kAnd, kOr, kNot, kEdge, kCompare, kHas, kExists, kForall };
  Kind kind = Kind::kTrue;
  std::vector<Formula> kids;       ///< kAnd/kOr: operands; kNot: one; kExists: body; kForall: guard, body
  PatternEdge edge;                ///< kEdge; for kCompare / kHas on an edge attribute, the edge
  std::string var, attr;           ///< kCompare / kHas (var empty: the attribute is the edge's)
  graph::Symbol attr_symbol;       ///< `attr`, interned (like PatternEdge::symbol)
  CompareOp op = CompareOp::kEq;   ///< kCompare
  graph::Value literal;            ///< kCompare
  std::vector<PatternNode> vars;   ///< kExists / kForall
  SourceLoc loc;
};

/// "For every binding of `vars` matching `lhs` (anchored on the rule's match), also rewrite it
/// into `rhs`" - e.g. the objects a robot carries move rooms with it.
struct ForallEffect {
  std::vector<PatternNode> vars;
  Pattern lhs, rhs;
  SourceLoc loc;
};

struct Rule {
  std::string name;
  bool active = true;
  int cost = 1;
  Pattern lhs, rhs;
  std::optional<Formula> precondition;
  std::vector<ForallEffect> foralls;
  SourceLoc loc;
};

/// A forbidden pattern: after every merge each replica looks for it around what changed.
struct Constraint {
  std::string name;
  Pattern forbid;
  std::optional<Formula> where;
  std::string repair_agent;  ///< the agent (name) that repairs a violation; empty: nobody
  SourceLoc loc;
};

struct Grammar {
  std::string name;
  TypeSystem types;
  bool allow_attributes = false;
  bool allow_rt_poses = false;
  bool allow_rt_moves = false;
  std::vector<Rule> rules;
  std::vector<Constraint> constraints;
  const Rule* rule(std::string_view name) const;
};

/// Parses a grammar; errors read "file:line:column: expected ..., found ...".
Result<Grammar> parse_grammar(std::string_view text, std::string_view source = "grammar");
Result<Grammar> load_grammar_file(const std::string& path);

/// Which rule a transaction applies, with the node each variable matched.
struct RuleMatch {
  std::string rule;
  std::vector<std::pair<std::string, graph::NodeId>> binding;  ///< sorted by variable
};

/// A forbidden pattern found in the graph. Equal on every replica holding the same state.
struct Violation {
  std::string constraint;
  std::vector<std::pair<std::string, graph::NodeId>> binding;  ///< sorted by variable
  std::string to_string(const graph::Graph& g) const;
  friend bool operator==(const Violation&, const Violation&) = default;
};

/// Checks transactions and states against a grammar. Cost follows the rule's size, not the
/// graph's: matches are anchored on the changed elements.
class GrammarChecker {
 public:
  explicit GrammarChecker(Grammar g);
  ~GrammarChecker();
  GrammarChecker(GrammarChecker&&) noexcept;
  GrammarChecker& operator=(GrammarChecker&&) noexcept;

  const Grammar& grammar() const;

  /// Validates a pending transaction against `g` (its state before the transaction). On
  /// refusal, kRefused with a message naming the closest rule and what failed.
  Status check(const graph::Graph& g, const std::vector<graph::TxnOp>& ops, RuleMatch* match = nullptr) const;
  /// Re-checks a transaction against one named rule and binding (cheap: no search).
  Status verify(const graph::Graph& g, const std::vector<graph::TxnOp>& ops, const RuleMatch& claim) const;
  /// Verifies an incoming delta against the receiver's state before the merge: its structural
  /// changes must be the application of the rule it claims (GraphDelta::rule, ::binding), and its
  /// other changes allowed. Exact when the receiver's state around the match equals the sender's;
  /// a concurrent change of that neighbourhood can make a valid delta fail here (the merged-state
  /// check is what catches the outcome of such races).
  Status verify_delta(const graph::Graph& before, const graph::GraphDelta& d) const;
  /// Violations of the constraints that involve any of `anchors` (e.g. nodes a merge touched).
  std::vector<Violation> violations_around(const graph::Graph& g, const std::vector<graph::NodeId>& anchors) const;
  /// Every violation in the graph (a full scan, for tests and start-up).
  std::vector<Violation> all_violations(const graph::Graph& g) const;
  /// True if `v` is still a violation of `g`, exactly as violations_around() would report it
  /// (searching only its own constraint, from one of its nodes).
  bool still_violated(const graph::Graph& g, const Violation& v) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace quiver::agents
