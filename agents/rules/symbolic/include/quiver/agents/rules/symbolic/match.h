#pragma once
/// @file
/// Patterns and formulas compiled against a Vocabulary, matched and evaluated on symbolic
/// States. Variables are slots of a Binding (a vector of node indices); compiling a pattern or a
/// formula assigns the slots, so that matching does no string work.
///
/// Meaning as in the grammar (docs/grammar.md): a pattern's variables match distinct nodes
/// (injective), of their type or a subtype; its edges must exist, its negated edges must not.
/// Formulas: and, or, not, edges, `=` of two variables, exists and forall (over distinct new
/// nodes in Quiver's dialect, over every node of the type in AGM's). Attribute comparisons
/// cannot be read in a symbolic state: compiling one fails (a note names it).

#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/symbolic/state.h"

namespace quiver::agents::inline rules::symbolic {

using Binding = std::vector<NodeIx>;  ///< per slot; kNoNode: unbound

/// Slots of named variables while compiling (a quantifier may shadow an outer name).
struct Scope {
  std::unordered_map<std::string, int> slot;
  int slots = 0;
  /// A new slot for `var` (shadowing any outer one).
  int add(const std::string& var) {
    slot[var] = slots;
    return slots++;
  }
  int find(const std::string& var) const {
    auto it = slot.find(var);
    return it == slot.end() ? -1 : it->second;
  }
};

struct CEdge {
  int from = -1, to = -1;  ///< slots
  LabelIx label = 0;
  bool negated = false;
  friend bool operator==(const CEdge&, const CEdge&) = default;
};

/// A compiled formula.
struct CFormula {
  Formula::Kind kind = Formula::Kind::kTrue;
  std::vector<CFormula> kids;
  CEdge edge;                                  ///< kEdge; kSame: edge.from, edge.to
  std::vector<std::pair<int, TypeIx>> vars;    ///< kExists / kForall: slot, type
  bool distinct = true;
};

/// Compiles `f` with the variables of `scope` (quantifiers add slots to it).
/// @returns false, with `why`, for what a symbolic state cannot answer (attributes) or a variable
///   the scope lacks.
bool compile(const Formula& f, Vocabulary& voc, Scope& scope, CFormula& out, std::string& why);

/// Evaluates `f` in `s` with `b` (sized to the scope's slots).
bool eval(const State& s, const Vocabulary& voc, const CFormula& f, Binding& b);

/// A compiled pattern: its k-th variable is slot `slots[k]`; matching follows `steps`, each
/// step's candidates from an edge to a bound node when it has one.
struct CPattern {
  std::vector<int> slots;
  std::vector<TypeIx> types;  ///< per variable
  std::vector<std::string> names;
  std::vector<CEdge> edges;
  struct Step {
    int var = -1;             ///< the variable (index into slots)
    int via = -1;             ///< index of a positive edge to a bound variable (candidates), or -1
    std::vector<int> checks;  ///< edges to check once `var` is bound (indices)
  };
  std::vector<Step> steps;
  std::vector<int> initial_checks;  ///< edges between variables bound before matching
  /// Plans the matching order given which slots are bound before matching starts.
  void plan(const std::vector<bool>& prebound);
};

/// Adds the variables and edges of `p` to `scope` and compiles them. Variables already in
/// `scope` (constants, a rule's other side) keep their slot.
CPattern compile(const Pattern& p, Vocabulary& voc, Scope& scope);

/// Calls `each` for every injective match of `p` extending `b` (slots of `p` unbound in `b`
/// are matched; bound ones are checked), until it returns false. Matched nodes differ from each
/// other and from the pattern's bound slots. @returns false if `each` stopped it.
bool match(const State& s, const Vocabulary& voc, const CPattern& p, Binding& b,
           const std::function<bool(Binding&)>& each);

}  // namespace quiver::agents::inline rules::symbolic
