// Grammars (docs/grammar.md): quiver.Grammar (parsed .aggl text) and quiver.GrammarGuard, which
// checks every local transaction of a standalone Graph against it. An Agent takes its grammar at
// construction (Agent(grammar=...)).

#include "common.h"
#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"

namespace quiver::python {
namespace {

using agents::Grammar;
using agents::GrammarChecker;
using agents::GrammarGuard;

using PyGuard = OnGraph<GrammarGuard>;

}  // namespace

void bind_grammar(py::module_& m) {
  py::class_<Grammar>(m, "Grammar", "A graph grammar: node types, rules (LHS => RHS) and constraints.")
      .def_static("parse", [](const std::string& text, const std::string& source) {
             return unwrap(agents::parse_grammar(text, source));
           }, py::arg("text"), py::arg("source") = "grammar",
           "Parses grammar text; InvalidArgumentError reads 'source:line:column: expected ..., found ...'.")
      .def_static("load", [](const std::string& path) { return unwrap(agents::load_grammar_file(path)); },
                  py::arg("path"))
      .def_readonly("name", &Grammar::name)
      .def_property_readonly("rules", [](const Grammar& g) {
             std::vector<std::string> out;
             for (const auto& r : g.rules) out.push_back(r.name);
             return out;
           })
      .def_property_readonly("constraints", [](const Grammar& g) {
        std::vector<std::string> out;
        for (const auto& c : g.constraints) out.push_back(c.name);
        return out;
      });

  py::class_<PyGuard>(m, "GrammarGuard",
                      "Checks every local transaction of a standalone Graph against a grammar (after install()): "
                      "a change that is not one rule application raises RefusedError at commit and changes "
                      "nothing.")
      .def(py::init([](const GraphHandle& h, const Grammar& g, const std::string& agent_name) {
             if (h.owner.owned()) {
               raise(make_error(ErrorCode::kInvalidArgument, "GrammarGuard(): give an agent its grammar with Agent(grammar=...)"));
             }
             PyGuard p;
             p.h = h;
             p.obj = std::make_unique<GrammarGuard>(*h.graph, GrammarChecker(g), agent_name);
             return p;
           }), py::arg("graph"), py::arg("grammar"), py::arg("agent_name") = "")
      .def("install", [](PyGuard& p) { p.get("install").install(); }, "Makes the graph refuse transactions the grammar does not allow.")
      .def("tick", [](PyGuard& p) { p.get("tick").tick(); }, "Performs pending repairs.")
      .def("violations", [](PyGuard& p) {
             py::list out;
             const auto& checker = p.get("violations").checker();
             for (const auto& v : checker.all_violations(*p.h.graph)) {
               py::dict binding;
               for (const auto& [var, id] : v.binding) binding[py::str(var)] = id;
               out.append(py::make_tuple(v.constraint, binding));
             }
             return out;
           }, "Every constraint violation in the graph: [(constraint, {variable: NodeId})].")
      .def_property_readonly("violations_seen", [](PyGuard& p) { return p.get("violations_seen").violations_seen(); })
      .def_property_readonly("deltas_unverified", [](PyGuard& p) { return p.get("deltas_unverified").deltas_unverified(); });
}

}  // namespace quiver::python
