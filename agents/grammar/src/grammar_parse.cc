// Grammar files: a hand-written lexer and recursive-descent parser. Every error names
// file:line:column, what was expected and what was found.

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

#include "quiver/agents/grammar/grammar.h"
#include "quiver/graph/limits.h"

namespace quiver::agents {

void TypeSystem::declare(const std::string& type, const std::string& base) { parent_[type] = base; }

bool TypeSystem::is_a(std::string_view type, std::string_view base) const {
  std::string_view t = type;
  for (int guard = 0; guard < 1000; ++guard) {
    if (t == base) return true;
    auto it = parent_.find(t);
    if (it == parent_.end() || it->second.empty()) return false;
    t = it->second;
  }
  return false;
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

struct Token {
  enum Kind { kIdent, kNumber, kString, kSymbol, kEnd } kind = kEnd;
  std::string text;
  SourceLoc loc;
};

class Lexer {
 public:
  explicit Lexer(std::string_view s) : s_(s) {}

  // Returns false and fills `err` on a lexical error.
  bool run(std::vector<Token>& out, std::string& err, SourceLoc& err_loc) {
    while (true) {
      skip_space();
      Token t;
      t.loc = {line_, col_};
      if (i_ >= s_.size()) {
        t.kind = Token::kEnd;
        out.push_back(t);
        return true;
      }
      char c = s_[i_];
      if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        t.kind = Token::kIdent;
        while (i_ < s_.size()) {
          char d = s_[i_];
          bool inner = std::isalnum(static_cast<unsigned char>(d)) || d == '_';
          // A '-' continues a word (rt-poses) unless it starts an arrow.
          bool dash = d == '-' && i_ + 1 < s_.size() && s_[i_ + 1] != '>' &&
                      (std::isalnum(static_cast<unsigned char>(s_[i_ + 1])) || s_[i_ + 1] == '_');
          if (!inner && !dash) break;
          t.text += d;
          advance();
        }
      } else if (std::isdigit(static_cast<unsigned char>(c)) ||
                 ((c == '-' || c == '.') && i_ + 1 < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_ + 1])))) {
        t.kind = Token::kNumber;
        while (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.' || s_[i_] == 'e' ||
                                  s_[i_] == 'E' || ((s_[i_] == '-' || s_[i_] == '+') && !t.text.empty() &&
                                                    (t.text.back() == 'e' || t.text.back() == 'E')) ||
                                  (t.text.empty() && s_[i_] == '-'))) {
          t.text += s_[i_];
          advance();
        }
      } else if (c == '"') {
        t.kind = Token::kString;
        advance();
        while (i_ < s_.size() && s_[i_] != '"') {
          if (s_[i_] == '\n') {
            err = "unterminated string";
            err_loc = t.loc;
            return false;
          }
          if (s_[i_] == '\\' && i_ + 1 < s_.size()) advance();
          t.text += s_[i_];
          advance();
        }
        if (i_ >= s_.size()) {
          err = "unterminated string";
          err_loc = t.loc;
          return false;
        }
        advance();
      } else {
        t.kind = Token::kSymbol;
        static const char* two[] = {"->", "=>", "==", "!=", "<=", ">="};
        for (const char* op : two)
          if (s_.substr(i_, 2) == op) t.text = op;
        if (t.text.empty()) {
          if (std::string("{}():!.,<>;").find(c) == std::string::npos) {
            err = std::string("unexpected character '") + c + "'";
            err_loc = t.loc;
            return false;
          }
          t.text = std::string(1, c);
        }
        for (std::size_t k = 0; k < t.text.size(); ++k) advance();
      }
      out.push_back(std::move(t));
    }
  }

 private:
  void advance() {
    if (s_[i_] == '\n') {
      ++line_;
      col_ = 1;
    } else {
      ++col_;
    }
    ++i_;
  }
  void skip_space() {
    while (i_ < s_.size()) {
      if (std::isspace(static_cast<unsigned char>(s_[i_]))) {
        advance();
      } else if (s_[i_] == '#') {
        while (i_ < s_.size() && s_[i_] != '\n') advance();
      } else {
        break;
      }
    }
  }
  std::string_view s_;
  std::size_t i_ = 0;
  int line_ = 1, col_ = 1;
};

struct ParseError {
  SourceLoc loc;
  std::string message;
};

class Parser {
 public:
  Parser(std::vector<Token> toks, std::string source) : t_(std::move(toks)), src_(std::move(source)) {}

  Result<Grammar> run() {
    try {
      file();
    } catch (const ParseError& e) {
      return make_error(ErrorCode::kMalformed,
                        src_ + ":" + std::to_string(e.loc.line) + ":" + std::to_string(e.loc.column) + ": " + e.message);
    }
    return std::move(g_);
  }

 private:
  const Token& peek(std::size_t k = 0) const { return t_[std::min(p_ + k, t_.size() - 1)]; }
  static std::string describe(const Token& t) {
    switch (t.kind) {
      case Token::kEnd: return "the end of the file";
      case Token::kString: return "string \"" + t.text + "\"";
      case Token::kNumber: return "number " + t.text;
      default: return "'" + t.text + "'";
    }
  }
  [[noreturn]] void fail(const std::string& expected, const Token& at) {
    throw ParseError{at.loc, "expected " + expected + ", found " + describe(at)};
  }
  [[noreturn]] void fail_at(SourceLoc loc, const std::string& msg) { throw ParseError{loc, msg}; }
  bool is(const char* sym) const { return peek().kind == Token::kSymbol && peek().text == sym; }
  bool is_word(const char* w) const { return peek().kind == Token::kIdent && peek().text == w; }
  Token take() { return t_[p_ < t_.size() - 1 ? p_++ : p_]; }
  void expect(const char* sym, const std::string& context) {
    if (!is(sym)) fail(std::string("'") + sym + "' " + context, peek());
    take();
  }
  std::string ident(const std::string& what) {
    if (peek().kind != Token::kIdent) fail(what, peek());
    // Rule, variable, type and label names travel in deltas: the limits table bounds them.
    if (peek().text.size() > graph::limits::kMaxNameBytes)
      fail_at(peek().loc, "a name of " + std::to_string(peek().text.size()) + " bytes (the limit is " +
                              std::to_string(graph::limits::kMaxNameBytes) + ")");
    return take().text;
  }

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
    return PatternNode{var, type, loc};
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
    r.rhs = pattern("the right-hand side of rule '" + r.name + "'", {});
    for (const auto& n : r.rhs.nodes)
      if (const PatternNode* l = r.lhs.node(n.var); l && l->type != n.type)
        fail_at(n.loc, "variable '" + n.var + "' changes type between the sides of rule '" + r.name + "'");
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

  std::vector<Token> t_;
  std::size_t p_ = 0;
  std::string src_;
  Grammar g_;
};

}  // namespace

Result<Grammar> parse_grammar(std::string_view text, std::string_view source) {
  std::vector<Token> toks;
  std::string err;
  SourceLoc loc;
  if (!Lexer(text).run(toks, err, loc))
    return make_error(ErrorCode::kMalformed,
                      std::string(source) + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column) + ": " + err);
  return Parser(std::move(toks), std::string(source)).run();
}

Result<Grammar> load_grammar_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kIo, "load_grammar_file(): cannot open '" + path + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_grammar(ss.str(), path);
}

}  // namespace quiver::agents
