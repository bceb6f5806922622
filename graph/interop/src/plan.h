#pragma once
// Private: a source world read and checked, not yet applied — what both importers produce — and
// the one place that turns it into graph changes: names mapped, RT edges checked (one parent,
// no loop, no cycle), RT link attributes moved to the child, everything committed in one
// transaction or not at all.

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/interop/interop.h"
#include "quiver/base/result.h"

namespace quiver::interop::internal {

using Attrs = std::vector<std::pair<std::string, graph::Value>>;

/// Prefix of the child attributes that hold an RT link's attributes (the graph's own).
using graph::kRtAttrPrefix;

struct PlanNode {
  std::string id;    ///< the source id, as text
  std::string type;
  std::string name;  ///< the name the file asks for (empty: `<type>_<id>`)
  Attrs attrs;
  std::string where;  ///< "file:/pointer" or "file:line: <symbol ...>", for messages
};

struct PlanEdge {
  std::size_t from = 0, to = 0;  ///< indices into Plan::nodes
  std::string type;
  Attrs attrs;
  std::string where;
};

struct PlanRt {
  std::size_t parent = 0, child = 0;
  graph::Pose pose;  ///< X_PC in metres
  Attrs attrs;       ///< the link's other attributes (go to the child, prefixed)
  std::string where;
};

struct Plan {
  std::vector<PlanNode> nodes;
  std::unordered_map<std::string, std::size_t> by_id;
  std::vector<PlanEdge> edges;
  std::vector<PlanRt> rts;
  std::vector<std::string> warnings;
  /// The RT link attributes the format's pose is written to: a child's own attribute
  /// `rt:<one of these>` could not be written back onto its link, so the file is refused.
  bool (*is_link_pose_key)(std::string_view key) = nullptr;

  /// Adds a node; false if its id is taken (the caller reports it).
  bool add_node(PlanNode n);
  /// The node of a source id, or nullptr.
  const std::size_t* find(const std::string& id) const;
};

/// Applies `plan` to `g` in one transaction (docs/interop.md, "Names"): every check first, then
/// the changes. Errors carry the element's `where`; `g` is unchanged on any error.
Result<ImportReport> apply_plan(graph::Graph& g, Plan& plan, const ImportOptions& options);

/// `where` + ": " + message, as a kMalformed error.
Error malformed(const std::string& where, const std::string& what);

/// When `text` is plainly not of the format `wanted` (kDsrJson or kAgmXml), what it is and which
/// command takes it ("this is an AGM XML world (root <AGMModel>); use quiver import-agm");
/// empty when it may be the wanted format (then its own parser tells what is wrong).
std::string wrong_format(std::string_view text, WorldFormat wanted);

}  // namespace quiver::interop::internal
