// The reader of AGM's syntax that the .aggl grammar parser and the .aggt mission parser share:
// names, numbers, a graph of typed nodes and labelled links, and the text AGM ignores after a
// section's formula.

#include "agm_reader.h"

#include <cmath>

namespace quiver::agents::inline rules::internal {

std::string AgmReader::name_token(const std::string& what) {
  const Token& t = peek();
  if (t.kind != Token::kIdent && t.kind != Token::kNumber) fail(what, t);
  check_name(t);
  return take().text;
}

int AgmReader::number(const Token& t, const std::string& what) {
  if (t.kind != Token::kNumber) fail(what, t);
  try {
    return static_cast<int>(std::lround(std::stod(t.text)));
  } catch (...) {
    fail_at(t.loc, "number '" + t.text + "' is out of range");
  }
}

// { v:type(x,y) ... a->b(label)[*] ... }
Pattern AgmReader::graph(const std::string& open, const std::string& context, const char* node,
                         const TypeUse& on_type, const TypeUse& on_bang) {
  expect("{", open);
  Pattern p;
  std::vector<PatternEdge> edges;
  while (!is("}")) {
    const SourceLoc start = peek().loc;
    std::string a = name_token("a node v:type, a link a->b(label) or '}' in " + context);
    if (is(":")) {
      take();
      PatternNode n;
      n.var = std::move(a);
      n.loc = start;
      const Token t = peek();
      n.type = name_token("a node type after ':'");
      if (on_type) on_type(t);
      if (is("(")) {
        take();
        const int x = number(peek(), "the node's x position");
        take();
        expect(",", "between the node's x and y positions");
        const int y = number(peek(), "the node's y position");
        take();
        expect(")", "to close the node's position");
        n.pos = std::make_pair(x, y);
      }
      if (p.node(n.var))
        fail_at(start, std::string(node) + " '" + n.var + "' is declared twice in " + context);
      p.nodes.push_back(std::move(n));
      continue;
    }
    if (!is("->"))
      fail("':' (a node v:type) or '->' (a link a->b(label)) after '" + a + "'", peek());
    take();
    PatternEdge e;
    e.from = std::move(a);
    e.loc = start;
    e.to = name_token("the link's target after '->'");
    expect("(", "and a link label after '" + e.from + "->" + e.to + "'");
    if (is("!")) {
      // AGM's parser reads and then ignores a '!' here; its editor negates with a trailing '*'.
      if (on_bang) on_bang(peek());
      take();
    }
    e.label = name_token("a link label");
    e.symbol = graph::Symbol(e.label);
    expect(")", "to close the link label");
    if (is("*")) {
      take();
      e.negated = true;  // AGM: the link must not exist
    }
    edges.push_back(std::move(e));
  }
  take();
  for (const PatternEdge& e : edges)
    for (const std::string& v : {e.from, e.to})
      if (!p.node(v))
        fail_at(e.loc, std::string("link uses undeclared ") + node + " '" + v + "' in " + context);
  p.edges = std::move(edges);
  return p;
}

void AgmReader::ignore_rest(const char* section, std::vector<std::string>& notes) {
  if (is("}")) return;
  const Token first = peek();
  while (!is("}") && !at_end()) {
    if (is("{")) fail("'}' to close the " + std::string(section), peek());
    take();
  }
  if (at_end()) fail("'}' to close the " + std::string(section), peek());
  notes.push_back(located(src_, first.loc,
                          "text after the " + std::string(section) + "'s formula, from " +
                              describe(first) + ", is ignored, as AGM's parser does"));
}

}  // namespace quiver::agents::inline rules::internal
