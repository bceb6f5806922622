// Missions as AGM's .aggt targets state them: parsed, compiled for planners, and checked against a world, with
// what is missing when they do not hold.
#include "quiver/agents/rules/mission/mission.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

// The AGGL lexer, the reader of AGM's syntax and AGM's formula parser are the grammar module's
// (private headers; the dependency points down: a target is written in the grammar's own syntax).
#include "agm_reader.h"
#include "aggl_agm_formula.h"
#include "grammar_lexer.h"
#include "xml_target.h"

namespace quiver::agents::inline rules {
namespace {

using internal::AgmReader;
using internal::ParseError;
using internal::Token;
using symbolic::Binding;
using symbolic::kNoNode;
using symbolic::NodeIx;

class MissionParser : public AgmReader {
 public:
  MissionParser(std::vector<Token> toks, std::string source) : AgmReader(std::move(toks), std::move(source)) {}

  Result<Mission> run() {
    Mission m;
    m.source = src_;
    try {
      if (is("{")) graph(m);
      section("precondition", m.notes, [&] {
        std::set<std::string> scope;
        for (const PatternNode& n : m.pattern.nodes) scope.insert(n.var);
        m.formula = internal::parse_agm_precondition(*this, scope, [](const Token&) {});
      });
      if (!at_end()) fail("the end of the mission (a target is '{ nodes links }' then 'precondition { }')", peek());
    } catch (const ParseError& e) {
      return make_error(ErrorCode::kMalformed, internal::located(src_, e.loc, e.message));
    }
    return m;
  }

 private:
  // { v:type(x,y) ... a->b(label)[*] ... }; a node whose name is a number is a constant.
  void graph(Mission& m) {
    m.pattern = AgmReader::graph("to open the target graph", "the target", "node", nullptr, nullptr);
    for (const PatternNode& n : m.pattern.nodes)
      m.constant.push_back(std::isdigit(static_cast<unsigned char>(n.var[0])) != 0);
  }
};

std::string edge_text(const PatternEdge& e) {
  return e.from + "->" + e.to + "(" + e.label + ")" + (e.negated ? "*" : "");
}

// A file of another kind given as a mission: what it is, or "" when it may be a target.
// Where the text's first token starts: after blanks and comment lines (# or //), which grammars
// and targets both begin with.
std::size_t first_token(std::string_view text) {
  std::size_t at = 0;
  for (;;) {
    at = text.find_first_not_of(" \t\r\n", at);
    if (at == std::string_view::npos) return at;
    if (text[at] != '#' && text.substr(at, 2) != "//") return at;
    at = text.find('\n', at);
    if (at == std::string_view::npos) return at;
  }
}

std::string other_kind(std::string_view text) {
  const auto first = first_token(text);
  if (first == std::string_view::npos) return "";
  const auto next = text.find_first_not_of(" \t\r\n", first + 1);
  if ((text[first] == '{' && next != std::string_view::npos && text[next] == '"') || text[first] == '[')
    return "this is JSON (a world file?), not a mission";
  if (text.find("\n===") != std::string_view::npos || text.substr(first, 5) == "name=" ||
      text.substr(first, 13) == "spacePattern=" || text.substr(first, 8) == "grammar ")
    return "this is a grammar (.aggl: a domain's rules), not a mission";
  return "";
}

}  // namespace

bool Mission::is_constant(std::string_view var) const {
  for (std::size_t i = 0; i < pattern.nodes.size(); ++i)
    if (pattern.nodes[i].var == var) return constant[i];
  return false;
}

Result<Mission> parse_mission(std::string_view text, std::string_view source) {
  if (internal::looks_like_xml(text)) return internal::parse_xml_target(text, source);
  if (std::string kind = other_kind(text); !kind.empty())
    return make_error(ErrorCode::kMalformed, std::string(source) + ": " + kind +
                                                 " (a mission is an AGM target: a .aggt file, or an AGM XML target "
                                                 "with the root <AGMModel>)");
  std::vector<Token> toks;
  std::string err;
  SourceLoc loc;
  if (!internal::lex(text, internal::Dialect::kAgm, toks, err, loc))
    return make_error(ErrorCode::kMalformed, internal::located(source, loc, err));
  return MissionParser(std::move(toks), std::string(source)).run();
}

Result<Mission> load_mission_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kIo, "load_mission_file(): cannot read '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_mission(ss.str(), path);
}

Result<CompiledMission> compile_mission(const Mission& m, symbolic::World& world) {
  CompiledMission c;
  symbolic::Scope scope;
  c.pattern = symbolic::compile(m.pattern, world.vocabulary, scope);
  std::vector<bool> prebound(m.pattern.nodes.size(), false);
  c.prebound.assign(scope.slots, kNoNode);
  for (std::size_t k = 0; k < m.pattern.nodes.size(); ++k) {
    if (!m.constant[k]) continue;
    prebound[k] = true;
    const NodeIx n = world.find(m.pattern.nodes[k].var);
    if (n == kNoNode) c.unresolved.push_back(m.pattern.nodes[k].var);
    c.prebound[c.pattern.slots[k]] = n;
  }
  c.pattern.plan(prebound);
  if (m.formula) {
    std::string why;
    symbolic::CFormula f;
    if (!symbolic::compile(*m.formula, world.vocabulary, scope, f, why))
      return make_error(ErrorCode::kInvalidArgument, m.source + ": the mission's formula: " + why);
    c.formula = std::move(f);
  }
  c.slots = scope.slots;
  c.prebound.resize(c.slots, kNoNode);
  return c;
}

bool mission_holds(const symbolic::State& s, const symbolic::Vocabulary& voc, const CompiledMission& m,
                   Binding* binding) {
  if (!m.unresolved.empty()) return false;
  for (std::size_t k = 0; k < m.pattern.slots.size(); ++k) {
    const NodeIx n = m.prebound[m.pattern.slots[k]];
    if (n != kNoNode && !s.alive(n)) return false;
  }
  Binding b = m.prebound;
  bool found = false;
  symbolic::match(s, voc, m.pattern, b, [&](Binding& full) {
    if (m.formula && !symbolic::eval(s, voc, *m.formula, full)) return true;
    found = true;
    if (binding) *binding = full;
    return false;
  });
  return found;
}

namespace {

// Branch and bound over assignments where a variable may stay unmatched: the assignment that
// satisfies the most nodes and links.
struct BestPartial {
  const symbolic::State& s;
  const symbolic::Vocabulary& voc;
  const CompiledMission& m;
  std::size_t budget;
  std::size_t visited = 0;
  int best = -1;
  Binding best_binding;
  std::vector<int> order;  // variable indices (into pattern.slots), constants excluded

  int edge_score(const Binding& b, const symbolic::CEdge& e) const {
    const NodeIx a = b[e.from], c = b[e.to];
    if (a == kNoNode || c == kNoNode) return e.negated ? 1 : 0;
    return s.has_edge(a, c, e.label) != e.negated ? 1 : 0;
  }
  int score(const Binding& b) const {
    int sc = 0;
    for (std::size_t k = 0; k < m.pattern.slots.size(); ++k) sc += b[m.pattern.slots[k]] != kNoNode;
    for (const symbolic::CEdge& e : m.pattern.edges) sc += edge_score(b, e);
    return sc;
  }
  void run(Binding& b, std::size_t i) {
    if (++visited > budget) return;
    if (i == order.size()) {
      const int sc = score(b);
      if (sc > best) {
        best = sc;
        best_binding = b;
      }
      return;
    }
    // Upper bound: every remaining variable and every link still open satisfied.
    int bound = 0;
    for (std::size_t k = 0; k < m.pattern.slots.size(); ++k) bound += b[m.pattern.slots[k]] != kNoNode;
    bound += static_cast<int>(order.size() - i);
    for (const symbolic::CEdge& e : m.pattern.edges) {
      const bool open = std::any_of(order.begin() + static_cast<long>(i), order.end(), [&](int k) {
        return m.pattern.slots[k] == e.from || m.pattern.slots[k] == e.to;
      });
      bound += open ? 1 : edge_score(b, e);
    }
    if (bound <= best) return;
    const int k = order[i];
    const int slot = m.pattern.slots[k];
    for (NodeIx n = 0; n < s.size(); ++n) {
      if (!s.alive(n) || !voc.is_a(s.type(n), m.pattern.types[k])) continue;
      if (std::find(b.begin(), b.end(), n) != b.end()) continue;
      b[slot] = n;
      run(b, i + 1);
      b[slot] = kNoNode;
      if (visited > budget) return;
    }
    run(b, i + 1);  // left unmatched
  }
};

}  // namespace

MissionReport check_mission(const Mission& m, const CompiledMission& cm, const symbolic::World& world,
                            const symbolic::State& s, std::size_t budget) {
  MissionReport r;
  r.total = static_cast<int>(m.pattern.nodes.size() + m.pattern.edges.size());
  const symbolic::Vocabulary& voc = world.vocabulary;
  auto name_of = [&](NodeIx n) {
    std::string label = world.label(n);
    if (n < world.names.size() && world.names[n] != label) label += " (" + world.names[n] + ")";
    return label;
  };
  Binding full;
  if (mission_holds(s, voc, cm, &full)) {
    r.holds = true;
    r.satisfied = r.total;
    for (std::size_t k = 0; k < m.pattern.nodes.size(); ++k)
      r.binding.emplace_back(m.pattern.nodes[k].var, world.label(full[cm.pattern.slots[k]]));
    return r;
  }
  BestPartial bp{s, voc, cm, budget, 0, -1, {}, {}};
  Binding b = cm.prebound;
  // Constants that are absent or of the wrong type stay unmatched.
  for (std::size_t k = 0; k < m.pattern.nodes.size(); ++k) {
    const int slot = cm.pattern.slots[k];
    if (!m.constant[k]) {
      bp.order.push_back(static_cast<int>(k));
      continue;
    }
    const NodeIx n = b[slot];
    if (n == kNoNode) {
      r.missing.push_back("node " + m.pattern.nodes[k].var + ":" + m.pattern.nodes[k].type +
                          ": the world has no node with that id");
    } else if (!s.alive(n) || !voc.is_a(s.type(n), cm.pattern.types[k])) {
      r.missing.push_back("node " + m.pattern.nodes[k].var + ":" + m.pattern.nodes[k].type + ": " +
                          (s.alive(n) ? "node " + name_of(n) + " is a " + voc.type_name(s.type(n))
                                      : std::string("the world has no node with that id")));
      b[slot] = kNoNode;
    }
  }
  bp.best_binding = b;
  bp.run(b, 0);
  r.exhaustive = bp.visited <= budget;
  const Binding& best = bp.best_binding;
  r.satisfied = bp.best < 0 ? 0 : bp.best;
  for (std::size_t k = 0; k < m.pattern.nodes.size(); ++k) {
    const NodeIx n = best[cm.pattern.slots[k]];
    if (n != kNoNode) {
      r.binding.emplace_back(m.pattern.nodes[k].var, world.label(n));
    } else if (!m.constant[k]) {
      r.missing.push_back("node " + m.pattern.nodes[k].var + ":" + m.pattern.nodes[k].type +
                          ": no " + m.pattern.nodes[k].type + " fits");
    }
  }
  for (std::size_t i = 0; i < m.pattern.edges.size(); ++i) {
    const symbolic::CEdge& e = cm.pattern.edges[i];
    if (bp.edge_score(best, e)) continue;
    const PatternEdge& pe = m.pattern.edges[i];
    const NodeIx a = best[e.from], c = best[e.to];
    std::string line = "link " + edge_text(pe);
    if (a == kNoNode || c == kNoNode)
      line += ": an end is unmatched";
    else
      line += std::string(": ") + name_of(a) + " -[" + pe.label + "]-> " + name_of(c) +
              (pe.negated ? " exists and must not" : " is missing");
    r.missing.push_back(std::move(line));
  }
  if (r.missing.empty()) {
    // Every node and link is there under some assignment: the formula is what fails.
    r.missing.push_back("the precondition formula is false" +
                        std::string(bp.best == r.total ? " for every assignment that matches the graph" : ""));
  }
  return r;
}

MissionReport check_mission(const Mission& m, const graph::Graph& g, const TypeSystem& types, std::size_t budget) {
  symbolic::World world = symbolic::read_world(g, types);
  auto cm = compile_mission(m, world);
  if (!cm.ok()) {
    MissionReport r;
    r.missing.push_back(cm.error().message);
    return r;
  }
  return check_mission(m, *cm, world, world.state, budget);
}

}  // namespace quiver::agents
