#pragma once
/// @file
/// A shared vocabulary (docs/schema.md): the node types (with inheritance), the edge types (with
/// the node types each may join) and the attributes (value type, unit, range, which node or edge
/// types may hold them, which agents may write them) that every agent of a domain agrees on. Every
/// agent loads the same file; a change that breaks it is refused on local commit and never applied
/// where it arrives (schema_checks.h, schema_admission.h).
///
/// File (JSON):
///   { "quiver_schema": 1,
///     "open": false,                    // true: undeclared types and attributes pass unchecked
///     "node_types": { "object": {}, "mug": {"is": "object"}, "cup": {"is": ["object", "container"]} },
///     "edge_types": { "in": {"from": ["object", "robot"], "to": ["room"]}, "RT": {} },
///     "attributes": {
///       "battery": {"type": "double", "unit": "1", "min": 0, "max": 1, "on": ["robot"],
///                   "writers": ["battery"]},
///       "label":   {"type": "string"},
///       "pose":    {"type": "any"} } }
/// A base named in "is" must be declared in the file (in any order); an edge's "from"/"to" list
/// the node types allowed at that end (subtypes included; absent: any). An attribute's "type" is
/// a value type's name as world files write it (graph/value.h: "int32", "vec3f", ...) or "any"
/// (its value type may change); "min"/"max" bound scalar numbers; "on" lists node or edge types
/// (subtypes included) that may hold it; "writers" lists agent names ("*": every agent).
/// Attributes named `__...` are the runtime's own (locks) and never checked; an RT edge's
/// attribute `rt:<name>` (kept on its child) is checked as attribute `<name>` of edge type "RT".
///
/// Threading: a plain value; const members may be called from any thread.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/graph/symbol.h"
#include "quiver/graph/value.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline rules::schema {

struct AttributeSpec {
  std::optional<graph::ValueType> type;  ///< nullopt: "any"
  std::string unit;
  std::optional<double> min, max;
  std::vector<std::string> on;           ///< node or edge types that may hold it; empty: any
  std::vector<std::string> writers;      ///< agent names; empty: every agent
};

struct EdgeTypeSpec {
  std::vector<std::string> from, to;  ///< node types allowed at each end; empty: any
};

class Schema {
 public:
  /// Reads a schema file's text; errors name `where` and the entry at fault.
  static Result<Schema> parse(std::string_view json, const std::string& where);
  static Result<Schema> load(const std::string& path);
  /// The schema as its file writes it (keys sorted), parseable by parse().
  std::string to_json() const;

  /// Building (quiver schema infer): replaces an earlier declaration of the same name.
  void declare_node_type(const std::string& type, std::vector<std::string> bases = {});
  void declare_edge_type(const std::string& type, EdgeTypeSpec spec = {});
  void declare_attribute(const std::string& name, AttributeSpec spec);
  void set_open(bool open) { open_ = open; }

  /// Where it was read from (the file's path), for errors.
  const std::string& where() const { return where_; }
  bool open() const { return open_; }
  const std::map<std::string, std::vector<std::string>>& node_types() const { return node_types_; }
  const std::map<std::string, EdgeTypeSpec>& edge_types() const { return edge_types_; }
  const std::map<std::string, AttributeSpec>& attributes() const { return attributes_; }
  bool has_node_type(std::string_view type) const { return node_types_.count(std::string(type)) > 0; }
  bool has_edge_type(std::string_view type) const { return edge_types_.count(std::string(type)) > 0; }
  /// True if `type` is `base` or inherits from it (an undeclared type is only itself).
  bool is_a(std::string_view type, std::string_view base) const;

  // The checks every layer makes alike. Each error is kPermissionDenied and names the schema.
  /// A node of `type` may exist.
  Status check_node_type(graph::Symbol type) const;
  /// An edge of `type` may exist; `from`/`to` are its ends' node types, null when unknown (a
  /// received delta does not state them).
  Status check_edge(graph::Symbol type, graph::Symbol from, graph::Symbol to) const;
  /// Agent `writer` may give attribute `attr` of a node (or, `on_edge`, an edge) of type `owner`
  /// the value `v`.
  Status check_value(std::uint64_t writer, graph::Symbol owner, bool on_edge, graph::Symbol attr,
                     const graph::Value& v) const;
  /// The name attribute `attr` is declared under: the runtime's own (`__…`) are not declared
  /// (nullopt); an RT edge's `rt:<name>`, kept on its child (graph::kRtAttrPrefix), is `<name>`
  /// (and `*rt`, if given, is set).
  static std::optional<std::string> declared_name(std::string_view attr, bool* rt = nullptr);
  /// Whether `attr`'s value type may change (declared "any"; or undeclared in an open schema).
  bool allows_type_change(graph::Symbol attr) const;

 private:
  Status refuse(const std::string& what) const;
  bool holder_allowed(const AttributeSpec& a, const std::string& owner) const;

  std::string where_ = "schema";
  bool open_ = false;
  std::map<std::string, std::vector<std::string>> node_types_;  // type -> direct bases
  std::map<std::string, EdgeTypeSpec> edge_types_;
  std::map<std::string, AttributeSpec> attributes_;
};

}  // namespace quiver::agents::inline rules::schema
