#pragma once
/// @file
/// The parts rules are made of: node variables, edges, patterns and formulas over a match.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "quiver/graph/symbol.h"
#include "quiver/graph/value.h"

namespace quiver::agents::inline rules {

/// Where something was written: 1-based line and column.
struct SourceLoc {
  int line = 0;
  int column = 0;
};

struct PatternNode {
  std::string var;
  std::string type;
  SourceLoc loc;
  /// Where AGM's editor drew the node (`v:type(x,y)`): metadata for editors, never matched.
  std::optional<std::pair<int, int>> pos;
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
/// whether two variables are one node, exists / forall over extra node variables.
struct Formula {
  enum class Kind : std::uint8_t {
    kTrue,
    kFalse,
    kAnd,
    kOr,
    kNot,
    kEdge,
    kCompare,
    kHas,
    kExists,
    kForall,
    kSame
  };
  Kind kind = Kind::kTrue;
  std::vector<Formula>
      kids;               ///< kAnd/kOr: operands; kNot: one; kExists: body; kForall: guard, body
  PatternEdge edge;       ///< kEdge; for kCompare / kHas on an edge attribute, the edge;
                          ///< kSame: the two variables are edge.from and edge.to
  std::string var, attr;  ///< kCompare / kHas (var empty: the attribute is the edge's)
  graph::Symbol attr_symbol;      ///< `attr`, interned (like PatternEdge::symbol)
  CompareOp op = CompareOp::kEq;  ///< kCompare
  graph::Value literal;           ///< kCompare
  std::vector<PatternNode> vars;  ///< kExists / kForall (a variable may shadow an outer one)
  /// kExists / kForall: the quantified nodes differ from each other and from the nodes already
  /// bound (our dialect), or range over every node of their type (AGM's, where `=` tells them
  /// apart).
  bool distinct = true;
  SourceLoc loc;
};

}  // namespace quiver::agents
