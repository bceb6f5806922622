// A source world read and checked but not yet applied, and the one place that turns it into graph changes,
// committed in one transaction or not at all.
#include "plan.h"

#include <map>
#include <tuple>
#include <unordered_set>

#include "quiver/graph/limits.h"
#include "text_values.h"

namespace quiver::interop::internal {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

bool Plan::add_node(PlanNode n) {
  if (!by_id.emplace(n.id, nodes.size()).second) return false;
  nodes.push_back(std::move(n));
  return true;
}

const std::size_t* Plan::find(const std::string& id) const {
  auto it = by_id.find(id);
  return it == by_id.end() ? nullptr : &it->second;
}

Error malformed(const std::string& where, const std::string& what) {
  return make_error(ErrorCode::kMalformed, where + ": " + what);
}

std::string wrong_format(std::string_view text, WorldFormat wanted) {
  std::string root;
  const WorldFormat f = detect_format(text, &root);
  if (f == wanted) return "";
  const std::string urdf = root == "robot" ? "; a URDF robot: use quiver import-urdf" : "";
  switch (f) {
    case WorldFormat::kQuiverJson:
      return "this is a Quiver world file (\"quiver_world\"): it needs no import; use it as it is (quiver agent --world, "
             "quiver lookup, quiver render...)";
    case WorldFormat::kAgmXml: return "this is an AGM XML world (root <AGMModel>); use quiver import-agm";
    case WorldFormat::kDsrJson: return "this is a CORTEX DSR JSON world (\"DSRModel\"); use quiver import-dsr";
    case WorldFormat::kOtherXml:
      if (wanted == WorldFormat::kDsrJson) return "this is XML (root <" + root + ">), not a CORTEX DSR JSON world" + urdf;
      return "the root element is <" + root + ">, not <AGMModel>: not an AGM XML world" + urdf;
    case WorldFormat::kOtherJson:
      if (wanted == WorldFormat::kAgmXml) return "this is JSON, not an AGM XML world";
      return "";
    case WorldFormat::kUnknown:
      return "";
  }
  return "";
}

namespace {

Status check(const std::string& where, std::string_view what, std::string_view name) {
  Status s = graph::check_name(what, name);
  if (!s.ok()) return Error{s.error().code, where + ": " + s.error().message};
  return {};
}

/// Attributes as the graph takes them; a name given twice keeps its last value (with a warning).
Result<std::vector<std::pair<Symbol, Value>>> symbols_of(Attrs& attrs, const std::string& where, const char* what,
                                                         std::vector<std::string>& warnings) {
  std::vector<std::pair<Symbol, Value>> out;
  out.reserve(attrs.size());
  std::unordered_map<std::string, std::size_t> seen;
  for (auto& [name, value] : attrs) {
    if (Status s = check(where, std::string(what) + " name", name); !s.ok()) return s.error();
    auto sym = Symbol::make(name);
    if (!sym.ok()) return Error{sym.error().code, where + ": " + sym.error().message};
    if (auto it = seen.find(name); it != seen.end()) {
      warnings.push_back(where + ": " + what + " " + in_quotes(name) + " is given twice: the last value is kept");
      out[it->second].second = std::move(value);
      continue;
    }
    seen.emplace(name, out.size());
    out.emplace_back(*sym, std::move(value));
  }
  return out;
}

}  // namespace

Result<ImportReport> apply_plan(graph::Graph& g, Plan& plan, const ImportOptions& options) {
  ImportReport report;
  std::vector<std::string>& warnings = report.warnings;
  warnings = std::move(plan.warnings);
  const std::size_t n = plan.nodes.size();

  // Names: the file's, mapped where Quiver cannot take them; a name taken earlier in the file is
  // given the symbol's id as a suffix once every asked-for name is placed.
  std::vector<std::string> names(n);
  std::unordered_set<std::string> taken;
  std::vector<std::size_t> clashing;
  for (std::size_t i = 0; i < n; ++i) {
    PlanNode& node = plan.nodes[i];
    if (Status s = check(node.where, "the type", node.type); !s.ok()) return s.error();
    std::string name = node.name.empty() ? node.type + "_" + node.id : node.name;
    if (name.find('~') != std::string::npos) {
      std::string mapped = name;
      for (char& c : mapped)
        if (c == '~') c = '-';
      warnings.push_back(node.where + ": the name " + in_quotes(name) + " holds '~' (reserved in Quiver names): named " +
                         in_quotes(mapped));
      name = std::move(mapped);
    }
    if (Status s = check(node.where, "the name", name); !s.ok()) return s.error();
    if (g.find_node(name))
      return make_error(ErrorCode::kAlreadyExists, node.where + ": the graph already has a node named " + in_quotes(name));
    if (!taken.insert(name).second) clashing.push_back(i);
    names[i] = std::move(name);
  }
  for (std::size_t i : clashing) {
    const PlanNode& node = plan.nodes[i];
    const std::string base = names[i] + "_" + node.id;
    std::string name = base;
    for (int k = 2; taken.count(name) || g.find_node(name); ++k) name = base + "_" + std::to_string(k);
    if (Status s = check(node.where, "the name", name); !s.ok()) return s.error();
    warnings.push_back(node.where + ": the name " + in_quotes(names[i]) + " is taken by an earlier symbol: named " +
                       in_quotes(name));
    taken.insert(name);
    names[i] = std::move(name);
  }

  // RT links: one parent per child (a repeated link: the last one counts), no loop, no cycle.
  std::vector<std::size_t> rt_of(n, SIZE_MAX);  // index into plan.rts of each child's link
  for (std::size_t r = 0; r < plan.rts.size(); ++r) {
    const PlanRt& rt = plan.rts[r];
    if (rt.parent == rt.child) return malformed(rt.where, "an RT link from a symbol to itself (a frame is not its own parent)");
    std::size_t& slot = rt_of[rt.child];
    if (slot != SIZE_MAX) {
      const PlanRt& before = plan.rts[slot];
      if (before.parent != rt.parent)
        return malformed(rt.where, "symbol " + plan.nodes[rt.child].id + " already has an RT parent (symbol " +
                                       plan.nodes[before.parent].id + ", " + before.where + ")");
      warnings.push_back(rt.where + ": a second RT link between the same symbols: this one is kept");
    }
    slot = r;
  }
  {
    // 0: not visited, 1: on the current path, 2: done.
    std::vector<std::uint8_t> state(n, 0);
    std::vector<std::size_t> path;
    for (std::size_t start = 0; start < n; ++start) {
      std::size_t v = start;
      path.clear();
      while (state[v] == 0 && rt_of[v] != SIZE_MAX) {
        state[v] = 1;
        path.push_back(v);
        v = plan.rts[rt_of[v]].parent;
      }
      if (state[v] == 1) return malformed(plan.rts[rt_of[v]].where, "the RT links form a cycle through symbol " + plan.nodes[v].id);
      for (std::size_t p : path) state[p] = 2;
      state[v] = 2;
    }
  }

  // The node attributes, with the RT links' attributes moved to their children.
  std::vector<std::vector<std::pair<Symbol, Value>>> node_attrs(n);
  for (std::size_t i = 0; i < n; ++i) {
    PlanNode& node = plan.nodes[i];
    if (rt_of[i] != SIZE_MAX) {
      PlanRt& rt = plan.rts[rt_of[i]];
      if (plan.is_link_pose_key)
        for (const auto& [own, v] : node.attrs)
          if (own.size() > kRtAttrPrefix.size() && own.compare(0, kRtAttrPrefix.size(), kRtAttrPrefix) == 0 &&
              plan.is_link_pose_key(std::string_view(own).substr(kRtAttrPrefix.size())))
            return malformed(node.where, "the attribute " + in_quotes(own) + " names the pose key " +
                                             in_quotes(own.substr(kRtAttrPrefix.size())) + " of the RT link from symbol " +
                                             plan.nodes[rt.parent].id +
                                             " (attributes prefixed rt: are that link's): it could not be written back; rename it");
      for (auto& [key, value] : rt.attrs) {
        std::string moved = std::string(kRtAttrPrefix) + key;
        for (const auto& [own, v] : node.attrs)
          if (own == moved)
            return malformed(rt.where, "the link attribute " + in_quotes(key) + " would be kept on symbol " + node.id +
                                           " as " + in_quotes(moved) + ", an attribute it already has");
        node.attrs.emplace_back(std::move(moved), std::move(value));
      }
    }
    auto attrs = symbols_of(node.attrs, node.where, "the attribute", warnings);
    if (!attrs.ok()) return attrs.error();
    node_attrs[i] = std::move(*attrs);
  }

  // Symbolic links: a repeated (src, dst, label) keeps its first place and its last attributes.
  std::vector<std::vector<std::pair<Symbol, Value>>> edge_attrs(plan.edges.size());
  std::vector<bool> edge_kept(plan.edges.size(), true);
  {
    std::map<std::tuple<std::size_t, std::size_t, std::string>, std::size_t> first;
    for (std::size_t e = 0; e < plan.edges.size(); ++e) {
      PlanEdge& edge = plan.edges[e];
      if (Status s = check(edge.where, "the link label", edge.type); !s.ok()) return s.error();
      auto attrs = symbols_of(edge.attrs, edge.where, "the link attribute", warnings);
      if (!attrs.ok()) return attrs.error();
      auto [it, fresh] = first.emplace(std::make_tuple(edge.from, edge.to, edge.type), e);
      if (!fresh) {
        warnings.push_back(edge.where + ": a second link " + in_quotes(edge.type) + " between the same symbols: its attributes are kept");
        edge_attrs[it->second] = std::move(*attrs);
        edge_kept[e] = false;
        continue;
      }
      edge_attrs[e] = std::move(*attrs);
    }
  }

  if (options.strict && !warnings.empty())
    return make_error(ErrorCode::kRefused, warnings.front() + " (refused: strict import, " +
                                               std::to_string(warnings.size()) + " warning" +
                                               (warnings.size() == 1 ? "" : "s") + ")");

  auto tx = g.begin();
  tx.reserve(n + plan.edges.size() + plan.rts.size());
  std::vector<NodeId> ids(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto id = tx.create_node(plan.nodes[i].type, names[i], std::move(node_attrs[i]));
    if (!id.ok()) return Error{id.error().code, plan.nodes[i].where + ": " + id.error().message};
    ids[i] = *id;
  }
  for (std::size_t e = 0; e < plan.edges.size(); ++e) {
    if (!edge_kept[e]) continue;
    const PlanEdge& edge = plan.edges[e];
    Status s = tx.insert_edge(ids[edge.from], ids[edge.to], std::string_view(edge.type), std::move(edge_attrs[e]));
    if (!s.ok()) return Error{s.error().code, edge.where + ": " + s.error().message};
    ++report.edges;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (rt_of[i] == SIZE_MAX) continue;
    const PlanRt& rt = plan.rts[rt_of[i]];
    Status s = tx.set_rt(ids[rt.parent], ids[rt.child], rt.pose, 0);
    if (!s.ok()) return Error{s.error().code, rt.where + ": " + s.error().message};
    ++report.rt_edges;
  }
  auto committed = tx.commit();
  if (!committed.ok()) return committed.error();
  report.nodes = n;
  return report;
}

}  // namespace quiver::interop::internal
