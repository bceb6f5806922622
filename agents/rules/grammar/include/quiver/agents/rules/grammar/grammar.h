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
/// negative edge (must not exist); a variable typed differently on the two sides is retyped
/// (retype.h). A transaction is valid when its structural changes are exactly ONE rule
/// application (typed, injective match, negative edges respected, precondition true, forall
/// effects applied to every match) and its other changes are allowed by `allow` lines.
///
/// The same types describe `.aggl` files as AGM's editor writes them (`name=...` header,
/// `types { (mug : object) }`, `v:type(x,y)`, `a->b(l)*`, s-expression preconditions and
/// effects, hierarchical, dormant and combo rules, include(...)): docs/grammar.md, "AGM's
/// dialect".

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "quiver/agents/rules/grammar/effect.h"
#include "quiver/agents/rules/grammar/pattern.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline rules {

/// Node types with inheritance: single in our dialect (`mug : object`), multiple in AGM's
/// (`(mug cup : object container)`).
class TypeSystem {
 public:
  /// Declares `type` as a subtype of every one of `bases`, which must already exist.
  void declare(const std::string& type, const std::vector<std::string>& bases);
  /// Declares `type` (optionally as a subtype of `base`, which must already exist).
  void declare(const std::string& type, const std::string& base = {});
  bool known(std::string_view type) const { return ancestors_.find(type) != ancestors_.end(); }
  /// True if `type` is `base` or inherits from it. An undeclared type is only itself.
  bool is_a(std::string_view type, std::string_view base) const;
  /// `type`'s direct bases, in declaration order (empty for an undeclared type).
  const std::vector<std::string>& bases(std::string_view type) const;
  /// Every declared type that is `base` or inherits from it, `base` first.
  std::vector<std::string> subtypes(std::string_view base) const;
  /// Declared types, in declaration order.
  const std::vector<std::string>& names() const { return order_; }

 private:
  // Looked up by string_view (no temporary strings on the check path).
  struct TextHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  struct Entry {
    std::vector<std::string> bases;      // direct
    std::vector<std::string> ancestors;  // the type itself and every base, transitively
  };
  std::unordered_map<std::string, Entry, TextHash, std::equal_to<>> ancestors_;
  std::vector<std::string> order_;
};

/// "For every binding of `vars` matching `lhs` (anchored on the rule's match), also rewrite it
/// into `rhs`" - e.g. the objects a robot carries move rooms with it.
struct ForallEffect {
  std::vector<PatternNode> vars;
  Pattern lhs, rhs;
  SourceLoc loc;
};

/// One step of a combo rule: rule `rule`, its variables named `alias.var` in the equivalences.
struct ComboAtom {
  std::string rule, alias;
  bool optional = false;  ///< the step may be left out
  SourceLoc loc;
};

/// `alias.var` in a combo rule's equivalences.
struct ComboVar {
  std::string alias, var;
  SourceLoc loc;
};

struct Rule {
  /// kNormal: one change applies it. kHierarchical: an abstract step a planner decomposes into a
  /// plan of other rules; no single change applies it. kCombo: a sequence of other rules applied
  /// as one change, with variables the equivalences identify.
  enum class Kind : std::uint8_t { kNormal, kHierarchical, kCombo };
  std::string name;
  Kind kind = Kind::kNormal;
  bool active = true;
  int cost = 1;
  double success = 1.0;                 ///< AGM's `success(p)`: probability the action succeeds
  bool dormant = false;                 ///< AGM: a planner uses it only once a rule activates it
  std::vector<std::string> activates;   ///< AGM: rules this one wakes up
  Pattern lhs, rhs;                     ///< a variable in both sides with two types is retyped
  std::optional<Formula> precondition;
  std::vector<ForallEffect> foralls;
  std::optional<Effect> effect;         ///< AGM's `effect { }`, applied with the rewrite
  std::vector<ComboAtom> atoms;         ///< kCombo: the steps, in order
  /// kCombo: classes of step variables that are one node.
  std::vector<std::vector<ComboVar>> equivalences;
  std::string file;                     ///< the file that defines it (includes bring others)
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
  enum class Dialect : std::uint8_t { kQuiver, kAgm };
  std::string name;
  Dialect dialect = Dialect::kQuiver;
  /// AGM's editor header (`name=...`, `fontName=...`): kept as written.
  std::vector<std::pair<std::string, std::string>> properties;
  /// Files include(...) brought in, resolved, in the order they were read.
  std::vector<std::string> includes;
  /// Remarks that do not stop loading, e.g. types a rule uses but no `types` block declares.
  std::vector<std::string> notes;
  TypeSystem types;
  bool allow_attributes = false;
  bool allow_rt_poses = false;
  bool allow_rt_moves = false;
  std::vector<Rule> rules;
  std::vector<Constraint> constraints;
  const Rule* rule(std::string_view name) const;
};

/// How include(...) files are found (AGM's dialect).
struct GrammarLoadOptions {
  /// Read include(...) files at all. parse_grammar() text has no directory of its own: without
  /// this an include(...) is an error (and a fuzzed text never reads files).
  bool read_includes = false;
  /// The directory relative include paths start from (a file's own directory).
  std::string base_dir;
  /// Searched after base_dir, like AGM's AGGLPATH.
  std::vector<std::string> include_dirs;
};

/// Parses a grammar in our dialect or AGM's (told apart by AGM's `key=value` header).
/// @param source names the text in errors and in Rule::file.
/// @returns the grammar (remarks that do not stop loading in Grammar::notes), or kMalformed
///   reading "source:line:column: expected ..., found ..."; an include(...) is kMalformed
///   unless `options.read_includes` (then a missing file is named too).
Result<Grammar> parse_grammar(std::string_view text, std::string_view source = "grammar");
Result<Grammar> parse_grammar(std::string_view text, std::string_view source, const GrammarLoadOptions& options);
/// Reads and parses a grammar file; include(...) paths are looked for relative to the including
/// file, then in `include_dirs` (docs/grammar.md, "AGM's dialect").
/// @returns the grammar, kIo if `path` cannot be read, or kMalformed naming file:line:column
///   (of the include, then of the included file's error), an include that cannot be found, or
///   an include cycle with its chain.
Result<Grammar> load_grammar_file(const std::string& path, std::vector<std::string> include_dirs = {});

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
/// graph's: matches are anchored on the changed elements. A hierarchical rule is never one
/// change (a planner decomposes it); a combo rule is checked as the composition of its steps,
/// and claims it by its name with variables `alias.var`.
class GrammarChecker {
 public:
  explicit GrammarChecker(Grammar g);
  ~GrammarChecker();
  GrammarChecker(GrammarChecker&&) noexcept;
  GrammarChecker& operator=(GrammarChecker&&) noexcept;

  const Grammar& grammar() const;
  /// What the checker leaves out, and why (e.g. a combo rule whose steps contradict each other).
  const std::vector<std::string>& notes() const;

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
