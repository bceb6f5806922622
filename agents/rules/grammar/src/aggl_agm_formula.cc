// AGM's s-expression preconditions and effects (AGM's parseQuantifiers.py reads the same
// productions; generateAGGLPlannerCode.py gives them their meaning):
//   (not F) (and F+) (or F+) (= a b) (forall x:t+ F) (exists x:t+ F) (when C F)
//   (create v T) (delete v) (retype v T) (LABEL a b)

#include "aggl_agm_formula.h"

namespace quiver::agents::inline rules::internal {
namespace {

class SexprParser {
 public:
  SexprParser(TokenCursor& in, const TypeUse& use_type) : in_(in), use_type_(use_type) {}

  Formula condition(const std::set<std::string>& scope) {
    Formula f;
    f.loc = in_.peek().loc;
    const Nesting nest(*this, f.loc);
    if (in_.is("<"))
      TokenCursor::fail_at(
          f.loc,
          "a function call <...>, which Quiver does not support (AGM's planner cannot "
          "evaluate one either)");
    in_.expect("(",
               "to open a condition, e.g. (in o r), (not ...), (and ...), (forall x:type ...)");
    const Token head = in_.peek();
    if (in_.is("=") || in_.is("==") || in_.is_word("eq")) {
      in_.take();
      same(f, scope);
    } else if (in_.is_word("not")) {
      in_.take();
      f.kind = Formula::Kind::kNot;
      f.kids.push_back(condition(scope));
    } else if (in_.is_word("and") || in_.is_word("or")) {
      f.kind = in_.take().text == "and" ? Formula::Kind::kAnd : Formula::Kind::kOr;
      do f.kids.push_back(condition(scope));
      while (!in_.is(")"));
    } else if (in_.is_word("forall") || in_.is_word("exists")) {
      quantifier(f, in_.take().text == "forall", scope);
    } else if (in_.is_word("when")) {
      // (when A B): B wherever A holds, i.e. (or (not A) B).
      in_.take();
      f.kind = Formula::Kind::kOr;
      Formula na;
      na.kind = Formula::Kind::kNot;
      na.loc = in_.peek().loc;
      na.kids.push_back(condition(scope));
      f.kids.push_back(std::move(na));
      f.kids.push_back(condition(scope));
    } else if (in_.is_word("create") || in_.is_word("delete") || in_.is_word("retype")) {
      TokenCursor::fail_at(
          head.loc,
          "'" + head.text + "' changes the graph: it belongs in an effect, not in a condition");
    } else {
      f.kind = Formula::Kind::kEdge;
      f.edge = link(scope);
    }
    in_.expect(")", "to close the " + describe_head(head));
    return f;
  }

  // `scope` grows with `create`, which names a node for the parts after it.
  Effect effect(std::set<std::string>& scope) {
    Effect e;
    e.loc = in_.peek().loc;
    const Nesting nest(*this, e.loc);
    in_.expect("(",
               "to open an effect, e.g. (in o r), (not (in o r)), (and ...), (forall x:type ...), "
               "(when ...)");
    const Token head = in_.peek();
    if (in_.is_word("and")) {
      in_.take();
      e.kind = Effect::Kind::kAll;
      do e.kids.push_back(effect(scope));
      while (!in_.is(")"));
    } else if (in_.is_word("forall")) {
      in_.take();
      e.kind = Effect::Kind::kForall;
      e.vars = vardecls("'forall'");
      std::set<std::string> inner = scope;
      for (const auto& v : e.vars) inner.insert(v.var);
      e.kids.push_back(effect(inner));
    } else if (in_.is_word("when")) {
      in_.take();
      e.kind = Effect::Kind::kWhen;
      e.condition = condition(scope);
      std::set<std::string> inner = scope;
      e.kids.push_back(effect(inner));
    } else if (in_.is_word("not")) {
      in_.take();
      e.kind = Effect::Kind::kRemoveEdge;
      const Token open = in_.peek();
      in_.expect("(",
                 "and an edge after 'not': an effect's 'not' removes an edge, (not (LABEL a b))");
      if (in_.peek().kind == Token::kIdent && keyword(in_.peek().text))
        TokenCursor::fail_at(
            open.loc, "(not (" + in_.peek().text +
                          " ...)): an effect's 'not' removes an edge, (not (LABEL a b)); AGM's "
                          "planner ignores any other 'not'");
      e.edge = link(scope);
      in_.expect(")", "to close the edge");
    } else if (in_.is_word("create") || in_.is_word("retype")) {
      e.kind = in_.take().text == "create" ? Effect::Kind::kCreate : Effect::Kind::kRetype;
      e.var = name(e.kind == Effect::Kind::kCreate ? "the variable of the new node"
                                                   : "the variable to retype");
      if (e.kind == Effect::Kind::kRetype) known(e.var, scope, head.loc);
      const Token t = in_.peek();
      e.type = name("a type");
      use_type_(t);
      if (e.kind == Effect::Kind::kCreate) scope.insert(e.var);
    } else if (in_.is_word("delete")) {
      in_.take();
      e.kind = Effect::Kind::kDelete;
      e.var = name("the variable of the node to delete");
      known(e.var, scope, head.loc);
    } else if (in_.is_word("or") || in_.is_word("exists") || in_.is("=") || in_.is("==") ||
               in_.is_word("eq")) {
      TokenCursor::fail_at(
          head.loc, "'" + head.text +
                        "' in an effect: effects add and remove edges and nodes (AGM's "
                        "planner refuses it too); put conditions in a (when CONDITION EFFECT)");
    } else {
      e.kind = Effect::Kind::kAddEdge;
      e.edge = link(scope);
    }
    in_.expect(")", "to close the " + describe_head(head));
    return e;
  }

  // forall / exists: `(forall x:t ... BODY)`.
  void quantifier(Formula& f, bool forall, const std::set<std::string>& scope) {
    f.vars = vardecls(forall ? "'forall'" : "'exists'");
    f.distinct = false;  // AGM: every node of the type, bound ones included
    std::set<std::string> inner = scope;
    for (const auto& v : f.vars) inner.insert(v.var);
    if (!forall) {
      f.kind = Formula::Kind::kExists;
      f.kids.push_back(condition(inner));
      return;
    }
    f.kind = Formula::Kind::kForall;
    if (in_.is("(") && in_.peek(1).kind == Token::kIdent && in_.peek(1).text == "when") {
      // (forall V (when C F)) = forall V { C } => { F }: C's edges anchor V.
      in_.take();
      in_.take();
      f.kids.push_back(condition(inner));
      f.kids.push_back(condition(inner));
      in_.expect(")", "to close the 'when'");
      return;
    }
    Formula body = condition(inner);
    if (body.kind == Formula::Kind::kNot) {
      // (forall V (not E)) = not (exists V E): E's edges anchor V.
      Formula ex;
      ex.kind = Formula::Kind::kExists;
      ex.loc = f.loc;
      ex.vars = std::move(f.vars);
      ex.distinct = false;
      ex.kids.push_back(std::move(body.kids[0]));
      f = Formula{};
      f.kind = Formula::Kind::kNot;
      f.loc = ex.loc;
      f.kids.push_back(std::move(ex));
      return;
    }
    Formula always;
    always.kind = Formula::Kind::kTrue;
    f.kids.push_back(std::move(always));
    f.kids.push_back(std::move(body));
  }

 private:
  // Formulas nest by recursion: bound it (a hostile file must not exhaust the stack).
  static constexpr int kMaxDepth = 100;
  struct Nesting {
    Nesting(SexprParser& p, SourceLoc at) : p_(p) {
      if (++p_.depth_ > kMaxDepth)
        TokenCursor::fail_at(
            at, "a formula nested more than " + std::to_string(kMaxDepth) + " levels deep");
    }
    ~Nesting() { --p_.depth_; }
    SexprParser& p_;
  };

  static bool keyword(const std::string& w) {
    for (const char* k :
         {"and", "or", "not", "forall", "exists", "when", "create", "delete", "retype", "eq"})
      if (w == k) return true;
    return false;
  }
  static std::string describe_head(const Token& head) {
    if (head.kind == Token::kIdent && keyword(head.text)) return "'" + head.text + "'";
    if (head.kind == Token::kSymbol && (head.text == "=" || head.text == "==")) return "'='";
    return "edge '" + head.text + "'";
  }

  // A name: a word or a number (AGM's node names may be numbers).
  std::string name(const std::string& what) {
    const Token& t = in_.peek();
    if (t.kind != Token::kIdent && t.kind != Token::kNumber) TokenCursor::fail(what, t);
    TokenCursor::check_name(t);
    return in_.take().text;
  }
  void known(const std::string& v, const std::set<std::string>& scope, SourceLoc loc) {
    if (!scope.count(v))
      TokenCursor::fail_at(loc,
                           "unknown variable '" + v + "' (not in the rule, nor quantified here)");
  }
  std::string var(const std::set<std::string>& scope, const std::string& what) {
    const SourceLoc loc = in_.peek().loc;
    std::string v = name(what);
    known(v, scope, loc);
    return v;
  }
  void same(Formula& f, const std::set<std::string>& scope) {
    f.kind = Formula::Kind::kSame;
    f.edge.from = var(scope, "a variable after '='");
    f.edge.to = var(scope, "a second variable after '='");
  }
  // LABEL a b
  PatternEdge link(const std::set<std::string>& scope) {
    PatternEdge e;
    e.loc = in_.peek().loc;
    e.label = name("an edge label, 'not', 'and', 'or', 'forall', 'exists', 'when' or '='");
    e.from = var(scope, "the edge's source variable after '" + e.label + "'");
    e.to = var(scope, "the edge's target variable");
    e.symbol = graph::Symbol(e.label);
    return e;
  }
  // x:type ... (one at least)
  std::vector<PatternNode> vardecls(const std::string& what) {
    std::vector<PatternNode> vars;
    while (in_.peek(1).kind == Token::kSymbol && in_.peek(1).text == ":") {
      PatternNode n;
      n.loc = in_.peek().loc;
      n.var = name("a variable");
      in_.take();
      const Token t = in_.peek();
      n.type = name("a type after ':'");
      use_type_(t);
      vars.push_back(std::move(n));
    }
    if (vars.empty())
      TokenCursor::fail("a variable and its type (x:type) after " + what, in_.peek());
    return vars;
  }

  TokenCursor& in_;
  const TypeUse& use_type_;
  int depth_ = 0;
};

}  // namespace

Formula parse_agm_precondition(TokenCursor& in, const std::set<std::string>& scope,
                               const TypeUse& use_type) {
  return SexprParser(in, use_type).condition(scope);
}

Effect parse_agm_effect(TokenCursor& in, const std::set<std::string>& scope,
                        const TypeUse& use_type) {
  std::set<std::string> s = scope;
  return SexprParser(in, use_type).effect(s);
}

}  // namespace quiver::agents::inline rules::internal
