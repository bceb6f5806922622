// Grammar files in our dialect (`grammar NAME`, `rule`, `constraint`, `allow`): a
// recursive-descent parser over grammar_lexer.h's tokens. Every error names file:line:column,
// what was expected and what was found. AGM's dialect: aggl_agm_parse.cc.

#include <algorithm>
#include <set>

#include "grammar_lexer.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules {

void TypeSystem::declare(const std::string& type, const std::vector<std::string>& bases) {
  Entry e;
  e.bases = bases;
  e.ancestors.push_back(type);
  for (const std::string& b : bases) {
    auto it = ancestors_.find(b);
    if (it == ancestors_.end()) continue;  // parsers refuse unknown bases
    for (const std::string& a : it->second.ancestors)
      if (std::find(e.ancestors.begin(), e.ancestors.end(), a) == e.ancestors.end()) e.ancestors.push_back(a);
  }
  if (ancestors_.find(type) == ancestors_.end()) order_.push_back(type);
  ancestors_[type] = std::move(e);
}

void TypeSystem::declare(const std::string& type, const std::string& base) {
  declare(type, base.empty() ? std::vector<std::string>{} : std::vector<std::string>{base});
}

bool TypeSystem::is_a(std::string_view type, std::string_view base) const {
  if (type == base) return true;
  auto it = ancestors_.find(type);
  if (it == ancestors_.end()) return false;
  for (const std::string& a : it->second.ancestors)
    if (a == base) return true;
  return false;
}

const std::vector<std::string>& TypeSystem::bases(std::string_view type) const {
  static const std::vector<std::string> none;
  auto it = ancestors_.find(type);
  return it == ancestors_.end() ? none : it->second.bases;
}

std::vector<std::string> TypeSystem::subtypes(std::string_view base) const {
  std::vector<std::string> out{std::string(base)};
  for (const std::string& t : order_)
    if (t != base && is_a(t, base)) out.push_back(t);
  return out;
}

const PatternNode* Pattern::node(std::string_view var) const {
  for (const auto& n : nodes)
    if (n.var == var) return &n;
  return nullptr;
}

const Rule* Grammar::rule(std::string_view name) const {
  for (const auto& r : rules)
    if (r.name == name) return &r;
  return nullptr;
}

namespace {

using internal::ParseError;
using internal::Token;

class Parser : public internal::TokenCursor {
 public:
  Parser(std::vector<Token> toks, std::string source) : TokenCursor(std::move(toks)), src_(std::move(source)) {}

  Result<Grammar> run() {
    try {
      file();
    } catch (const ParseError& e) {
      return make_error(ErrorCode::kMalformed, internal::located(src_, e.loc, e.message));
    }
    return std::move(g_);
  }

 private:
  void file() {
    if (is_word("grammar")) {
      take();
      g_.name = ident("a grammar name after 'grammar'");
    }
    while (peek().kind != Token::kEnd) {
      if (is_word("types")) types();
      else if (is_word("allow")) allow();
      else if (is_word("rule")) rule();
      else if (is_word("constraint")) constraint();
      else fail("'types', 'allow', 'rule' or 'constraint'", peek());
    }
  }

  void types() {
    take();
    expect("{", "to open the type list");
    while (!is("}")) {
      Token name = peek();
      std::string t = ident("a type name or '}'");
      std::string base;
      if (is(":")) {
        take();
        Token b = peek();
        base = ident("the base type after ':'");
        if (!g_.types.known(base)) fail_at(b.loc, "unknown base type '" + base + "' (declare it first)");
      }
      if (g_.types.known(t)) fail_at(name.loc, "type '" + t + "' is declared twice");
      g_.types.declare(t, base);
    }
    take();
  }

  void allow() {
    take();
    Token w = peek();
    std::string what = ident("'attributes', 'rt-poses' or 'rt-moves' after 'allow'");
    if (what == "attributes") g_.allow_attributes = true;
    else if (what == "rt-poses") g_.allow_rt_poses = true;
    else if (what == "rt-moves") g_.allow_rt_moves = true;
    else fail("'attributes', 'rt-poses' or 'rt-moves' after 'allow'", w);
  }

  PatternNode node_decl(const std::string& var, SourceLoc loc) {
    take();  // ':'
    Token tt = peek();
    std::string type = ident("a node type after ':'");
    if (!g_.types.known(type)) fail_at(tt.loc, "unknown type '" + type + "'");
    return PatternNode{var, type, loc, std::nullopt};
  }

  // { element* } where element = var:type | [!]a->b(label)
  Pattern pattern(const std::string& context, const std::set<std::string>& outer) {
    expect("{", "to open " + context);
    Pattern p;
    std::set<std::string> declared = outer;
    while (!is("}")) {
      bool neg = false;
      SourceLoc start = peek().loc;
      if (is("!")) {
        take();
        neg = true;
      }
      std::string a = ident("a node variable, an edge or '}' in " + context);
      if (is(":") && !neg) {
        PatternNode n = node_decl(a, start);
        if (p.node(a)) fail_at(start, "variable '" + a + "' is declared twice in " + context);
        declared.insert(a);
        p.nodes.push_back(std::move(n));
        continue;
      }
      if (!is("->")) fail("':' (a node declaration) or '->' (an edge) after '" + a + "'", peek());
      take();
      std::string b = ident("the edge's target variable after '->'");
      expect("(", "and an edge label after '" + a + "->" + b + "'");
      std::string label = ident("an edge label");
      expect(")", "to close the edge label");
      for (const std::string& v : {a, b})
        if (!declared.count(v)) fail_at(start, "edge uses undeclared variable '" + v + "'");
      p.edges.push_back(PatternEdge{a, b, label, neg, start, graph::Symbol(label)});
    }
    take();
    return p;
  }

  static std::set<std::string> vars_of(const Pattern& p) {
    std::set<std::string> vars;
    for (const auto& n : p.nodes) vars.insert(n.var);
    return vars;
  }

  std::vector<PatternNode> quantified_vars(const std::string& context) {
    std::vector<PatternNode> vars;
    do {
      if (is(",")) take();
      SourceLoc loc = peek().loc;
      std::string v = ident("a variable for " + context);
      if (!is(":")) fail("':' and a type after '" + v + "'", peek());
      vars.push_back(node_decl(v, loc));
    } while (is(","));
    return vars;
  }

  // formula := conj ('or' conj)* ; conj := unary ('and' unary)* ; ...
  Formula formula(const std::set<std::string>& scope) {
    return nary("or", Formula::Kind::kOr, &Parser::conj, scope);
  }
  Formula conj(const std::set<std::string>& scope) {
    return nary("and", Formula::Kind::kAnd, &Parser::unary, scope);
  }
  // operand (word operand)*, as one `kind` node when there are several operands.
  Formula nary(const char* word, Formula::Kind kind,
               Formula (Parser::*operand)(const std::set<std::string>&),
               const std::set<std::string>& scope) {
    Formula left = (this->*operand)(scope);
    if (!is_word(word)) return left;
    Formula f;
    f.kind = kind;
    f.loc = left.loc;
    f.kids.push_back(std::move(left));
    while (is_word(word)) {
      take();
      f.kids.push_back((this->*operand)(scope));
    }
    return f;
  }
  Formula unary(const std::set<std::string>& scope) {
    Formula f;
    f.loc = peek().loc;
    if (is_word("not")) {
      take();
      f.kind = Formula::Kind::kNot;
      f.kids.push_back(unary(scope));
      return f;
    }
    if (is("(")) {
      take();
      Formula inner = formula(scope);
      expect(")", "to close the parenthesis");
      return inner;
    }
    if (is_word("true") || is_word("false")) {
      f.kind = take().text == "true" ? Formula::Kind::kTrue : Formula::Kind::kFalse;
      return f;
    }
    if (is_word("exists") || is_word("forall")) {
      bool ex = take().text == "exists";
      f.kind = ex ? Formula::Kind::kExists : Formula::Kind::kForall;
      f.vars = quantified_vars(ex ? "'exists'" : "'forall'");
      std::set<std::string> inner = scope;
      for (const auto& v : f.vars) inner.insert(v.var);
      expect("{", ex ? "to open the body of 'exists'" : "to open the condition of 'forall'");
      f.kids.push_back(formula(inner));
      expect("}", "to close the body");
      if (!ex) {
        expect("=>", "after the condition of 'forall' (forall x:t { condition } => { formula })");
        expect("{", "to open the body of 'forall'");
        f.kids.push_back(formula(inner));
        expect("}", "to close the body of 'forall'");
      }
      return f;
    }
    if (is_word("has")) {  // has v.attr
      take();
      f.kind = Formula::Kind::kHas;
      f.var = ident("a variable after 'has'");
      expect(".", "and an attribute name after the variable");
      f.attr = ident("an attribute name");
      f.attr_symbol = graph::Symbol(f.attr);
      if (!scope.count(f.var)) fail_at(f.loc, "unknown variable '" + f.var + "'");
      return f;
    }
    std::string a = ident("a condition (an edge a->b(label), v.attr OP value, has, not, exists, forall, true, false)");
    if (!scope.count(a)) fail_at(f.loc, "unknown variable '" + a + "'");
    if (is("->")) {
      take();
      std::string b = ident("the edge's target variable");
      expect("(", "and an edge label");
      std::string label = ident("an edge label");
      expect(")", "to close the edge label");
      if (!scope.count(b)) fail_at(f.loc, "unknown variable '" + b + "'");
      f.kind = Formula::Kind::kEdge;
      f.edge = PatternEdge{a, b, label, false, f.loc, graph::Symbol(label)};
      if (!is(".")) return f;
      take();  // an edge attribute: a->b(label).attr OP value
      f.attr = ident("an edge attribute name");
      f.attr_symbol = graph::Symbol(f.attr);
    } else {
      expect(".", "'->' or '.' after '" + a + "'");
      f.var = a;
      f.attr = ident("an attribute name");
      f.attr_symbol = graph::Symbol(f.attr);
    }
    f.kind = Formula::Kind::kCompare;
    static const std::pair<const char*, CompareOp> ops[] = {{"==", CompareOp::kEq}, {"!=", CompareOp::kNe},
                                                            {"<=", CompareOp::kLe}, {">=", CompareOp::kGe},
                                                            {"<", CompareOp::kLt},  {">", CompareOp::kGt}};
    bool found = false;
    for (const auto& [sym, op] : ops)
      if (is(sym)) {
        take();
        f.op = op;
        found = true;
        break;
      }
    if (!found) fail("a comparison operator (==, !=, <, <=, >, >=)", peek());
    const Token lit = take();
    if (lit.kind == Token::kString) {
      f.literal = graph::Value(lit.text);
    } else if (lit.kind == Token::kNumber) {
      try {
        if (lit.text.find_first_of(".eE") != std::string::npos) f.literal = graph::Value(std::stod(lit.text));
        else f.literal = graph::Value(static_cast<std::int64_t>(std::stoll(lit.text)));
      } catch (...) {
        fail_at(lit.loc, "number '" + lit.text + "' is out of range");
      }
    } else if (lit.kind == Token::kIdent && (lit.text == "true" || lit.text == "false")) {
      f.literal = graph::Value(lit.text == "true");
    } else {
      fail("a string, number, true or false to compare with", lit);
    }
    return f;
  }

  void rule() {
    Token kw = take();
    Rule r;
    r.loc = kw.loc;
    r.file = src_;
    Token name = peek();
    r.name = ident("a rule name");
    if (g_.rule(r.name)) fail_at(name.loc, "rule '" + r.name + "' is defined twice");
    expect(":", "and 'active' or 'passive' after the rule name");
    Token kind = peek();
    std::string k = ident("'active' or 'passive'");
    if (k != "active" && k != "passive") fail("'active' or 'passive'", kind);
    r.active = k == "active";
    if (is("(")) {
      take();
      Token c = peek();
      if (c.kind != Token::kNumber) fail("a cost", c);
      r.cost = std::stoi(take().text);
      expect(")", "to close the cost");
    }
    expect("{", "to open rule '" + r.name + "'");
    r.lhs = pattern("the left-hand side of rule '" + r.name + "'", {});
    expect("=>", "between the two sides of rule '" + r.name + "'");
    r.rhs = pattern("the right-hand side of rule '" + r.name + "'", {});  // a type change retypes
    std::set<std::string> all = vars_of(r.lhs);
    all.merge(vars_of(r.rhs));
    while (!is("}")) {
      if (is_word("precondition")) {
        take();
        expect("{", "to open the precondition");
        r.precondition = formula(vars_of(r.lhs));
        expect("}", "to close the precondition");
      } else if (is_word("forall")) {
        ForallEffect fe;
        fe.loc = take().loc;
        fe.vars = quantified_vars("the forall effect");
        std::set<std::string> scope = all;
        for (const auto& v : fe.vars) scope.insert(v.var);
        expect("{", "to open the forall effect");
        fe.lhs = pattern("the left-hand side of the forall effect", scope);
        expect("=>", "between the two sides of the forall effect");
        fe.rhs = pattern("the right-hand side of the forall effect", scope);
        expect("}", "to close the forall effect");
        r.foralls.push_back(std::move(fe));
      } else {
        fail("'precondition', 'forall' or '}' to close rule '" + r.name + "'", peek());
      }
    }
    take();
    g_.rules.push_back(std::move(r));
  }

  void constraint() {
    Token kw = take();
    Constraint c;
    c.loc = kw.loc;
    c.name = ident("a constraint name");
    expect("{", "to open constraint '" + c.name + "'");
    if (!is_word("forbid")) fail("'forbid'", peek());
    take();
    c.forbid = pattern("the forbidden pattern of '" + c.name + "'", {});
    while (!is("}")) {
      if (is_word("where")) {
        take();
        expect("{", "to open the condition");
        c.where = formula(vars_of(c.forbid));
        expect("}", "to close the condition");
      } else if (is_word("repair")) {
        take();
        if (!is_word("by")) fail("'by' after 'repair'", peek());
        take();
        c.repair_agent = ident("the name of the agent that repairs violations");
        expect(":", "after the repairing agent");
        if (!is_word("delete")) fail("'delete oldest'", peek());
        take();
        if (!is_word("oldest")) fail("'oldest' (the only repair policy: delete the oldest edge of the match)", peek());
        take();
      } else {
        fail("'where', 'repair' or '}'", peek());
      }
    }
    take();
    g_.constraints.push_back(std::move(c));
  }

  std::string src_;
  Grammar g_;
};

}  // namespace

namespace internal {

Result<Grammar> parse_quiver_grammar(std::string_view text, std::string_view source) {
  std::vector<Token> toks;
  std::string err;
  SourceLoc loc;
  if (!lex(text, Dialect::kQuiver, toks, err, loc)) return make_error(ErrorCode::kMalformed, located(source, loc, err));
  return Parser(std::move(toks), std::string(source)).run();
}

}  // namespace internal

}  // namespace quiver::agents
