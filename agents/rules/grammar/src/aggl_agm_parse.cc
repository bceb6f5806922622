// AGM's dialect of AGGL, as AGM's editor writes it (AGM's own parser: parseAGGL.py):
//
//   name=domain              editor header: key=value lines, up to '==='
//   fontName=Arial
//   ===
//   types { (robot) (object) (mug cup : object) }   optional (older files have none), then '==='
//   ===
//   include(other.aggl)
//   [dormant] [hierarchical] NAME : active|passive(COST) [success(P)] [activates(R, ...)]
//   {
//     { v:type(x,y) ... a->b(label) a->b(label)* ... } => { ... }
//     [parameters { x:type ... }] [precondition { (...) }] [effect { (...) }]
//   }
//   COMBO : active(COST) { rule as alias [optional] ... where: alias.var = alias.var ... }
//
// Errors name file:line:column, what was expected and what was found.

#include <algorithm>
#include <cmath>
#include <set>

#include "agm_reader.h"
#include "grammar_parsers.h"

namespace quiver::agents::inline rules::internal {
namespace {

bool word_is(const Token& t, const char* w) {
  if (t.kind != Token::kIdent || t.text.size() != std::string_view(w).size()) return false;
  for (std::size_t i = 0; i < t.text.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(t.text[i])) != w[i]) return false;
  return true;
}

class AgmParser : public AgmReader {
 public:
  AgmParser(std::vector<Token> toks, std::string source, const IncludeFn& include)
      : AgmReader(std::move(toks), std::move(source)), include_(include) {}

  Result<Grammar> run() {
    g_.dialect = Grammar::Dialect::kAgm;
    // AGM's agents update attributes (poses of RT links included) outside the rules, with
    // symbol and edge updates its executive never checks; a structural change, moving an RT
    // link too, is a rule's.
    g_.allow_attributes = true;
    g_.allow_rt_poses = true;
    try {
      file();
    } catch (const ParseError& e) {
      return make_error(ErrorCode::kMalformed, located(src_, e.loc, e.message));
    }
    return std::move(g_);
  }

 private:
  void file() {
    header();
    if (is_word("types")) {
      types();
      expect("===", "after the types block (AGM's files separate it from the rules)");
    } else {
      typed_ = false;
    }
    while (!at_end()) {
      if (is_word("include") && peek(1).kind == Token::kSymbol && peek(1).text == "(")
        include();
      else
        rule();
    }
  }

  // key=value ... ===
  void header() {
    if (!(peek().kind == Token::kIdent || peek().kind == Token::kNumber) ||
        peek(1).kind != Token::kSymbol || peek(1).text != "=")
      fail("AGM's header, key=value lines ending with '==='", peek());
    while (!is("===")) {
      const Token key = peek();
      if (key.kind != Token::kIdent) fail("a header line key=value or '==='", key);
      take();
      expect("=", "after header key '" + key.text + "'");
      const Token value = peek();
      if (value.kind != Token::kIdent && value.kind != Token::kNumber)
        fail("a value for header key '" + key.text + "'", value);
      take();
      if (key.text == "name") g_.name = value.text;
      g_.properties.emplace_back(key.text, value.text);
    }
    take();
  }

  // types { (a b : base1 base2) ... }
  void types() {
    take();
    expect("{", "to open the type list");
    if (is("}")) fail("a type definition '(type ... [: base ...])'", peek());
    while (!is("}")) {
      expect("(", "to open a type definition '(type ... [: base ...])'");
      std::vector<Token> names;
      while (peek().kind == Token::kIdent || peek().kind == Token::kNumber) names.push_back(take());
      if (names.empty()) fail("a type name", peek());
      std::vector<std::string> bases;
      if (is(":")) {
        take();
        while (peek().kind == Token::kIdent || peek().kind == Token::kNumber) {
          const Token b = take();
          if (!g_.types.known(b.text))
            fail_at(b.loc, "unknown base type '" + b.text + "' (declare it first)");
          bases.push_back(b.text);
        }
        if (bases.empty()) fail("a base type after ':'", peek());
      }
      expect(")", "to close the type definition");
      for (const Token& n : names) {
        check_name(n);
        if (g_.types.known(n.text)) fail_at(n.loc, "type '" + n.text + "' is declared twice");
        g_.types.declare(n.text, bases);
      }
    }
    take();
  }

  // A type named by a rule: declared, or (AGM declares nothing) implicitly a type of its own.
  void use_type(const Token& t) {
    if (g_.types.known(t.text)) return;
    g_.types.declare(t.text, std::vector<std::string>{});
    if (typed_)
      g_.notes.push_back(located(
          src_, t.loc, "type '" + t.text + "' is not in the types block: it matches only itself"));
  }

  void include() {
    const Token kw = take();
    expect("(", "after 'include'");
    const Token path = peek();
    if (path.kind != Token::kString || path.text.empty()) fail("a file path", path);
    take();
    expect(")", "to close the include path");
    if (!include_)
      fail_at(kw.loc, "include(" + path.text +
                          ") needs a file to read: load the grammar with load_grammar_file()");
    Result<Grammar> inc = include_(path.text, kw.loc);
    if (!inc.ok()) throw ParseError{kw.loc, inc.error().message};
    merge(std::move(*inc), kw.loc);
  }

  // Rules of an included file join ours where the include stands; its types join ours too
  // (AGM takes only the rules, so a type only the included file declares was unknown to it).
  void merge(Grammar inc, SourceLoc at) {
    for (const std::string& t : inc.types.names()) {
      if (!g_.types.known(t)) {
        std::vector<std::string> bases;
        for (const std::string& b : inc.types.bases(t))
          if (g_.types.known(b)) bases.push_back(b);
        g_.types.declare(t, bases);
      } else if (g_.types.bases(t) != inc.types.bases(t)) {
        g_.notes.push_back(
            located(src_, at, "type '" + t + "' has other bases in the included file; ours stand"));
      }
    }
    for (std::string& f : inc.includes) g_.includes.push_back(std::move(f));
    for (std::string& n : inc.notes) g_.notes.push_back(std::move(n));
    for (Rule& r : inc.rules) add_rule(std::move(r));
  }

  // [dormant] [hierarchical] [dormant] [rule] NAME : active|passive(COST) [success(P)]
  // [activates(...)] { ... }
  void rule() {
    Rule r;
    r.file = src_;
    r.loc = peek().loc;
    bool more = true;
    while (more) {
      more = false;
      // A qualifier is a word followed by another name, not by ':' (then it is the rule's name).
      const bool qualifier = peek(1).kind != Token::kSymbol;
      if (qualifier && word_is(peek(), "dormant")) {
        take();
        r.dormant = more = true;
      } else if (qualifier && is_word("hierarchical")) {
        take();
        r.kind = Rule::Kind::kHierarchical;
        more = true;
      } else if (qualifier && is_word("rule")) {
        take();
        more = true;
      }
    }
    const Token name = peek();
    if (name.kind != Token::kIdent && name.kind != Token::kNumber)
      fail("a rule name, 'include(...)' or the end of the file", name);
    check_name(name);
    r.name = take().text;
    expect(":", "and 'active' or 'passive' after rule name '" + r.name + "'");
    const Token kind = peek();
    if (!word_is(kind, "active") && !word_is(kind, "passive")) fail("'active' or 'passive'", kind);
    r.active = word_is(take(), "active");
    if (is("(")) {
      take();
      r.cost = number(peek(), "a cost (an integer)");
      take();
      expect(")", "to close the cost");
    }
    if (word_is(peek(), "success")) {
      take();
      expect("(", "after 'success'");
      const Token p = peek();
      if (p.kind != Token::kNumber) fail("a probability of success", p);
      r.success = std::stod(take().text);
      if (!(r.success >= 0.0 && r.success <= 1.0))
        fail_at(p.loc, "a probability of success of " + p.text + " (not in [0, 1])");
      expect(")", "to close 'success'");
    }
    if (word_is(peek(), "activates")) {
      take();
      expect("(", "after 'activates'");
      do {
        if (is(",")) take();
        r.activates.push_back(ident("the name of a rule to activate"));
      } while (is(","));
      expect(")", "to close 'activates'");
    }
    expect("{", "to open rule '" + r.name + "'");
    if ((peek().kind == Token::kIdent || peek().kind == Token::kNumber) &&
        peek(1).kind == Token::kIdent && peek(1).text == "as") {
      if (r.kind == Rule::Kind::kHierarchical)
        fail_at(r.loc, "a hierarchical combo rule: AGM's rules are one or the other");
      combo(r);
    } else {
      sides(r);
    }
    expect("}", "to close rule '" + r.name + "'");
    add_rule(std::move(r));
  }

  // AGM appends every rule; its generated planner defines one method per name, so a later
  // definition of a name replaces the earlier one. So do we, and say so.
  void add_rule(Rule r) {
    for (Rule& old : g_.rules) {
      if (old.name != r.name) continue;
      g_.notes.push_back(located(r.file, r.loc,
                                 "rule '" + r.name + "' is defined again (first at " + old.file +
                                     ":" + std::to_string(old.loc.line) +
                                     "): the later definition stands, as "
                                     "in AGM's planner"));
      old = std::move(r);
      return;
    }
    g_.rules.push_back(std::move(r));
  }

  // { nodes links } => { nodes links } [parameters {}] [precondition {}] [effect {}]
  void sides(Rule& r) {
    r.lhs = side("the left-hand side of rule '" + r.name + "'");
    expect("=>", "between the two sides of rule '" + r.name + "'");
    r.rhs = side("the right-hand side of rule '" + r.name + "'");
    if (is_word("parameters")) {
      // Extra variables matched anywhere, named by the precondition and the effect.
      take();
      expect("{", "to open the parameters");
      while (!is("}")) {
        PatternNode n;
        n.loc = peek().loc;
        n.var = name_token("a parameter x:type or '}'");
        expect(":", "and a type after parameter '" + n.var + "'");
        const Token t = peek();
        n.type = name_token("a type");
        use_type(t);
        if (r.lhs.node(n.var) || r.rhs.node(n.var))
          fail_at(n.loc, "parameter '" + n.var + "' is a variable of the rule already");
        r.lhs.nodes.push_back(n);
        r.rhs.nodes.push_back(std::move(n));
      }
      take();
    }
    std::set<std::string> lhs_vars, all_vars;
    for (const auto& n : r.lhs.nodes) lhs_vars.insert(n.var);
    all_vars = lhs_vars;
    for (const auto& n : r.rhs.nodes) all_vars.insert(n.var);
    const TypeUse types = [this](const Token& t) { use_type(t); };
    section("precondition", g_.notes,
            [&] { r.precondition = parse_agm_precondition(*this, lhs_vars, types); });
    section("effect", g_.notes, [&] { r.effect = parse_agm_effect(*this, all_vars, types); });
    absent_after(r);
  }

  // A '*' link in the right-hand side that the left-hand side does not mention says the link is
  // absent after the change: the rule removes it if it is there (AGM's editor draws it so;
  // AGM's planner re-adds such links instead, docs/grammar.md). An effect does that.
  static void absent_after(Rule& r) {
    Effect removals;
    removals.kind = Effect::Kind::kAll;
    for (const PatternEdge& e : r.rhs.edges) {
      if (!e.negated) continue;
      bool mentioned = false;
      for (const PatternEdge& l : r.lhs.edges)
        mentioned = mentioned || (l.from == e.from && l.to == e.to && l.label == e.label);
      if (mentioned || !r.lhs.node(e.from) || !r.lhs.node(e.to)) continue;
      Effect x;
      x.kind = Effect::Kind::kRemoveEdge;
      x.edge = e;
      x.edge.negated = false;
      x.loc = e.loc;
      removals.kids.push_back(std::move(x));
    }
    if (removals.kids.empty()) return;
    if (r.effect)
      removals.kids.push_back(std::move(*r.effect));  // the rewrite first, then the effect
    r.effect = std::move(removals);
  }

  // A rule's side: its types declared (or refused), a '!' inside a link label noted.
  Pattern side(const std::string& context) {
    const TypeUse types = [this](const Token& t) { use_type(t); };
    const TypeUse bang = [this](const Token& t) {
      g_.notes.push_back(located(src_, t.loc,
                                 "'!' inside a link label is ignored, as AGM does: a '*' after "
                                 "the link negates it"));
    };
    return graph("to open " + context, context, "variable", types, bang);
  }

  // rule as alias [optional] ... where: alias.var = alias.var ...
  void combo(Rule& r) {
    r.kind = Rule::Kind::kCombo;
    while (!is_word("where")) {
      ComboAtom a;
      a.loc = peek().loc;
      a.rule =
          name_token("a rule name, or 'where:' after the steps of combo rule '" + r.name + "'");
      if (!is_word("as")) fail("'as' and an alias after '" + a.rule + "'", peek());
      take();
      a.alias = name_token("an alias after 'as'");
      if (is_word("optional")) {
        take();
        a.optional = true;
      }
      for (const ComboAtom& o : r.atoms)
        if (o.alias == a.alias)
          fail_at(a.loc, "alias '" + a.alias + "' is used twice in combo rule '" + r.name + "'");
      r.atoms.push_back(std::move(a));
    }
    take();
    expect(":", "after 'where'");
    while (!is("}")) {
      std::vector<ComboVar> cls;
      do {
        if (is("=")) take();
        const Token t = peek();
        const std::string ref = name_token("alias.variable in an equivalence");
        const auto dot = ref.find('.');
        if (dot == std::string::npos || dot == 0 || dot + 1 == ref.size() ||
            ref.find('.', dot + 1) != std::string::npos)
          fail("alias.variable", t);
        cls.push_back(ComboVar{ref.substr(0, dot), ref.substr(dot + 1), t.loc});
      } while (is("="));
      if (cls.size() < 2) fail("'=' and another alias.variable", peek());
      r.equivalences.push_back(std::move(cls));
    }
  }

  const IncludeFn& include_;
  Grammar g_;
  bool typed_ = true;  // the file has a types block
};

}  // namespace

Result<Grammar> parse_agm_grammar(std::string_view text, std::string_view source,
                                  const IncludeFn& include) {
  std::vector<Token> toks;
  std::string err;
  SourceLoc loc;
  if (!lex(text, Dialect::kAgm, toks, err, loc))
    return make_error(ErrorCode::kMalformed, located(source, loc, err));
  return AgmParser(std::move(toks), std::string(source), include).run();
}

}  // namespace quiver::agents::inline rules::internal
