// Grammar constraints: the violations a state holds around some nodes (the smallest binding of
// each, so every replica reports the same), whether one still holds, and all of them.

#include <algorithm>
#include <map>

#include "grammar_compiled.h"

namespace quiver::agents::inline rules {

using internal::Binding;
using internal::CompiledConstraint;
using internal::enumerate;
using internal::eval;

using graph::Graph;
using graph::NodeId;

std::string Violation::to_string(const Graph& g) const {
  std::string s = constraint + "(";
  for (std::size_t i = 0; i < binding.size(); ++i)
    s += (i ? ", " : "") + binding[i].first + "=" + g.name_of(binding[i].second);
  return s + ")";
}

std::vector<Violation> GrammarChecker::violations_around(const Graph& gr, const std::vector<NodeId>& anchors) const {
  return impl_->violations_around(gr, anchors, nullptr);
}

bool GrammarChecker::still_violated(const Graph& gr, const Violation& v) const {
  // Every binding over v's nodes maps some variable to its first node, so a search anchored
  // there alone finds them all (and so reports the same smallest one). A deleted node matches
  // nothing.
  if (v.binding.empty()) return false;
  for (const Violation& w : impl_->violations_around(gr, {v.binding.front().second}, &v.constraint))
    if (w == v) return true;
  return false;
}

std::vector<Violation> GrammarChecker::Impl::violations_around(const Graph& gr,
                                                               const std::vector<NodeId>& anchors,
                                                               const std::string* only) const {
  const TypeSystem& types = g.types;
  // A violation is identified by its constraint and its set of nodes; of the bindings that
  // produce it (symmetric patterns give several), the smallest is reported, so every replica
  // reports the same one whatever order it found them in.
  std::map<std::pair<std::string, std::vector<NodeId>>, Violation> found;
  for (const CompiledConstraint& cc : constraints) {
    const Constraint& con = *cc.con;
    if (only != nullptr && con.name != *only) continue;
    for (NodeId anchor : anchors) {
      if (!gr.has_node(anchor)) continue;
      const std::string& anchor_type = gr.type_of(anchor).str();
      for (std::size_t i = 0; i < con.forbid.nodes.size(); ++i) {
        const PatternNode& pv = con.forbid.nodes[i];
        if (!types.is_a(anchor_type, pv.type)) continue;
        Binding b;
        b[pv.var] = anchor;
        enumerate(gr, types, cc.rest[i], true, cc.guard.formula, cc.guard.edges, b, [&](Binding& m) {
          if (con.where && !eval(gr, types, *con.where, m)) return true;
          Violation v;
          v.constraint = con.name;
          std::vector<NodeId> nodes;
          for (const auto& [var, id] : m) {
            nodes.push_back(id);
            v.binding.emplace_back(var, id);
          }
          std::sort(nodes.begin(), nodes.end());
          std::sort(v.binding.begin(), v.binding.end());
          auto [it, fresh] = found.try_emplace({con.name, std::move(nodes)}, v);
          if (!fresh && v.binding < it->second.binding) it->second = std::move(v);
          return true;
        });
      }
    }
  }
  std::vector<Violation> out;
  for (auto& [key, v] : found) out.push_back(std::move(v));
  std::sort(out.begin(), out.end(), [](const Violation& a, const Violation& b) {
    if (a.constraint != b.constraint) return a.constraint < b.constraint;
    return a.binding < b.binding;
  });
  return out;
}

std::vector<Violation> GrammarChecker::all_violations(const Graph& gr) const { return violations_around(gr, gr.nodes()); }

}  // namespace quiver::agents
