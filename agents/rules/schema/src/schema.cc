// The shared vocabulary: its JSON file read and written, and the checks a node type, an edge and
// an attribute value get against it.
#include "quiver/agents/rules/schema/schema.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "quiver/base/hash.h"

namespace quiver::agents::inline rules::schema {
namespace {

using nlohmann::json;

// A string, or an array of strings, as a list; false when it is neither.
bool names(const json& j, std::vector<std::string>& out) {
  if (j.is_string()) {
    out.push_back(j.get<std::string>());
    return !out.back().empty();
  }
  if (!j.is_array()) return false;
  for (const auto& e : j) {
    if (!e.is_string() || e.get<std::string>().empty()) return false;
    out.push_back(e.get<std::string>());
  }
  return true;
}

bool number(const graph::Value& v, double& out) {
  switch (v.type()) {
    case graph::ValueType::kInt32: out = *v.get_if<std::int32_t>(); return true;
    case graph::ValueType::kInt64: out = static_cast<double>(*v.get_if<std::int64_t>()); return true;
    case graph::ValueType::kUInt32: out = *v.get_if<std::uint32_t>(); return true;
    case graph::ValueType::kUInt64: out = static_cast<double>(*v.get_if<std::uint64_t>()); return true;
    case graph::ValueType::kFloat: out = *v.get_if<float>(); return true;
    case graph::ValueType::kDouble: out = *v.get_if<double>(); return true;
    default: return false;
  }
}

std::string num(double d) {
  std::ostringstream s;
  s << d;
  return s.str();
}

std::string list(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : ", ") + ("'" + e + "'");
  return s;
}


}  // namespace

Result<Schema> Schema::parse(std::string_view text, const std::string& where) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range)
    return make_error(ErrorCode::kMalformed, where + ": JSON syntax error: " + e.what());
  }
  auto fail = [&](const std::string& what) { return make_error(ErrorCode::kMalformed, where + ": " + what); };
  if (!j.is_object() || !j.contains("quiver_schema"))
    return fail("a schema is a JSON object with \"quiver_schema\": 1 (docs/schema.md)");
  for (const auto& [key, v] : j.items())
    if (key != "quiver_schema" && key != "open" && key != "node_types" && key != "edge_types" && key != "attributes")
      return fail("unknown key \"" + key + "\" (expected \"quiver_schema\", \"open\", \"node_types\", \"edge_types\", \"attributes\")");
  if (j["quiver_schema"] != 1) return fail("\"quiver_schema\" must be 1 (the only version there is)");
  Schema s;
  s.where_ = where;
  if (j.contains("open")) {
    if (!j["open"].is_boolean()) return fail("\"open\" must be true or false");
    s.open_ = j["open"].get<bool>();
  }
  auto section = [&](const char* key) -> Result<const json*> {
    if (!j.contains(key)) return static_cast<const json*>(nullptr);
    if (!j[key].is_object()) return fail(std::string("\"") + key + "\" must be an object of names");
    return &j[key];
  };
  auto nodes = section("node_types");
  if (!nodes.ok()) return nodes.error();
  if (*nodes != nullptr)
    for (const auto& [type, spec] : (*nodes)->items()) {
      const std::string at = "node type '" + type + "'";
      if (type.empty()) return fail("a node type has an empty name");
      if (!spec.is_object()) return fail(at + ": expected an object ({} or {\"is\": BASES})");
      std::vector<std::string> bases;
      for (const auto& [key, v] : spec.items()) {
        if (key != "is") return fail(at + ": unknown key \"" + key + "\" (expected \"is\")");
        if (!names(v, bases)) return fail(at + ": \"is\" must be a type or a list of types");
      }
      s.node_types_[type] = std::move(bases);
    }
  for (const auto& [type, bases] : s.node_types_)
    for (const auto& b : bases)
      if (!s.node_types_.count(b)) return fail("node type '" + type + "': its base '" + b + "' is not declared");
  // Inheritance must not loop.
  for (const auto& [type, bases] : s.node_types_) {
    std::vector<std::string> todo = bases;
    std::set<std::string> seen;
    while (!todo.empty()) {
      std::string t = todo.back();
      todo.pop_back();
      if (t == type) return fail("node type '" + type + "' inherits from itself");
      if (!seen.insert(t).second) continue;
      for (const auto& b : s.node_types_[t]) todo.push_back(b);
    }
  }
  auto edges = section("edge_types");
  if (!edges.ok()) return edges.error();
  if (*edges != nullptr)
    for (const auto& [type, spec] : (*edges)->items()) {
      const std::string at = "edge type '" + type + "'";
      if (type.empty()) return fail("an edge type has an empty name");
      if (!spec.is_object()) return fail(at + ": expected an object ({}, or with \"from\" and \"to\")");
      EdgeTypeSpec e;
      for (const auto& [key, v] : spec.items()) {
        if (key != "from" && key != "to") return fail(at + ": unknown key \"" + key + "\" (expected \"from\", \"to\")");
        if (!names(v, key == "from" ? e.from : e.to)) return fail(at + ": \"" + key + "\" must be a list of node types");
      }
      for (const auto* ends : {&e.from, &e.to})
        for (const auto& t : *ends)
          if (!s.node_types_.count(t)) return fail(at + ": the node type '" + t + "' is not declared");
      s.edge_types_[type] = std::move(e);
    }
  auto attrs = section("attributes");
  if (!attrs.ok()) return attrs.error();
  if (*attrs != nullptr)
    for (const auto& [name, spec] : (*attrs)->items()) {
      const std::string at = "attribute '" + name + "'";
      if (name.empty()) return fail("an attribute has an empty name");
      if (!spec.is_object() || !spec.contains("type") || !spec["type"].is_string())
        return fail(at + ": expected an object with \"type\" (a value type's name, or \"any\")");
      AttributeSpec a;
      for (const auto& [key, v] : spec.items()) {
        if (key == "type") {
          const std::string t = v.get<std::string>();
          if (t != "any") {
            a.type = graph::value_type_from_string(t);
            if (!a.type) return fail(at + ": unknown value type '" + t + "' (int32, double, string, vec3f, ... or any)");
          }
        } else if (key == "unit") {
          if (!v.is_string()) return fail(at + ": \"unit\" must be a string");
          a.unit = v.get<std::string>();
        } else if (key == "min" || key == "max") {
          if (!v.is_number()) return fail(at + ": \"" + key + "\" must be a number");
          (key == "min" ? a.min : a.max) = v.get<double>();
        } else if (key == "on") {
          if (!names(v, a.on)) return fail(at + ": \"on\" must be a list of node or edge types");
          for (const auto& t : a.on)
            if (!s.node_types_.count(t) && !s.edge_types_.count(t))
              return fail(at + ": \"on\" names '" + t + "', which is neither a node type nor an edge type here");
        } else if (key == "writers") {
          if (!names(v, a.writers)) return fail(at + ": \"writers\" must be a list of agent names");
        } else {
          return fail(at + ": unknown key \"" + key + "\" (expected \"type\", \"unit\", \"min\", \"max\", \"on\", \"writers\")");
        }
      }
      if (a.min && a.max && *a.min > *a.max) return fail(at + ": \"min\" is above \"max\"");
      s.attributes_[name] = std::move(a);
    }
  return s;
}

Result<Schema> Schema::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kNotFound, path + ": cannot open the schema file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path);
}

std::string Schema::to_json() const {
  json j = json::object();
  j["quiver_schema"] = 1;
  if (open_) j["open"] = true;
  json nodes = json::object();
  for (const auto& [type, bases] : node_types_) {
    json spec = json::object();
    if (bases.size() == 1) spec["is"] = bases[0];
    else if (!bases.empty()) spec["is"] = bases;
    nodes[type] = spec;
  }
  j["node_types"] = nodes;
  json edges = json::object();
  for (const auto& [type, e] : edge_types_) {
    json spec = json::object();
    if (!e.from.empty()) spec["from"] = e.from;
    if (!e.to.empty()) spec["to"] = e.to;
    edges[type] = spec;
  }
  j["edge_types"] = edges;
  json attrs = json::object();
  for (const auto& [name, a] : attributes_) {
    json spec = json::object();
    spec["type"] = a.type ? graph::to_string(*a.type) : "any";
    if (!a.unit.empty()) spec["unit"] = a.unit;
    if (a.min) spec["min"] = *a.min;
    if (a.max) spec["max"] = *a.max;
    if (!a.on.empty()) spec["on"] = a.on;
    if (!a.writers.empty()) spec["writers"] = a.writers;
    attrs[name] = spec;
  }
  j["attributes"] = attrs;
  return j.dump(2) + "\n";
}

void Schema::declare_node_type(const std::string& type, std::vector<std::string> bases) {
  node_types_[type] = std::move(bases);
}

void Schema::declare_edge_type(const std::string& type, EdgeTypeSpec spec) { edge_types_[type] = std::move(spec); }

void Schema::declare_attribute(const std::string& name, AttributeSpec spec) { attributes_[name] = std::move(spec); }

bool Schema::is_a(std::string_view type, std::string_view base) const {
  if (type == base) return true;
  auto it = node_types_.find(std::string(type));
  if (it == node_types_.end()) return false;
  for (const auto& b : it->second)
    if (is_a(b, base)) return true;
  return false;
}

Status Schema::refuse(const std::string& what) const {
  return make_error(ErrorCode::kPermissionDenied, "the schema " + where_ + " " + what);
}

Status Schema::check_node_type(graph::Symbol type) const {
  if (open_ || node_types_.count(type.str())) return {};
  return refuse("declares no node type '" + type.str() + "'");
}

Status Schema::check_edge(graph::Symbol type, graph::Symbol from, graph::Symbol to) const {
  auto it = edge_types_.find(type.str());
  if (it == edge_types_.end()) {
    if (open_) return {};
    return refuse("declares no edge type '" + type.str() + "'");
  }
  auto allowed = [&](const std::vector<std::string>& types, graph::Symbol end) {
    if (types.empty() || end.is_null()) return true;
    return std::any_of(types.begin(), types.end(), [&](const std::string& t) { return is_a(end.str(), t); });
  };
  if (!allowed(it->second.from, from))
    return refuse("lets an edge '" + type.str() + "' start only at " + list(it->second.from) + ", not at a '" +
                  from.str() + "'");
  if (!allowed(it->second.to, to))
    return refuse("lets an edge '" + type.str() + "' end only at " + list(it->second.to) + ", not at a '" + to.str() +
                  "'");
  return {};
}

bool Schema::holder_allowed(const AttributeSpec& a, const std::string& owner) const {
  if (a.on.empty()) return true;
  return std::any_of(a.on.begin(), a.on.end(), [&](const std::string& t) { return is_a(owner, t); });
}

Status Schema::check_value(std::uint64_t writer, graph::Symbol owner, bool on_edge, graph::Symbol attr,
                           const graph::Value& v) const {
  bool rt = false;
  const auto declared = declared_name(attr.str(), &rt);
  if (!declared) return {};
  const std::string& name = *declared;
  std::string holder = owner.str();
  if (!on_edge && rt) {
    holder = "RT";
    on_edge = true;
  }
  auto it = attributes_.find(name);
  if (it == attributes_.end()) {
    if (open_) return {};
    return refuse("declares no attribute '" + name + "'");
  }
  const AttributeSpec& a = it->second;
  const std::string on = std::string(on_edge ? "an edge '" : "a node '") + holder + "'";
  if (!holder_allowed(a, holder))
    return refuse("lets only " + list(a.on) + " hold the attribute '" + name + "', not " + on);
  if (a.type && v.type() != *a.type)
    return refuse("declares the attribute '" + name + "' a " + graph::to_string(*a.type) + ", not a " +
                  graph::to_string(v.type()) + " (on " + on + ")");
  double x = 0;
  if ((a.min || a.max) && number(v, x)) {
    if (std::isnan(x) || (a.min && x < *a.min) || (a.max && x > *a.max))
      return refuse("bounds the attribute '" + name + "' to [" + (a.min ? num(*a.min) : "-inf") + ", " +
                    (a.max ? num(*a.max) : "inf") + "]" + (a.unit.empty() ? "" : " " + a.unit) + "; " + num(x) +
                    " is outside (on " + on + ")");
  }
  if (!a.writers.empty()) {
    const bool ok = std::any_of(a.writers.begin(), a.writers.end(),
                                [&](const std::string& w) { return w == "*" || fnv1a64(w) == writer; });
    if (!ok) return refuse("lets only " + list(a.writers) + " write the attribute '" + name + "' (on " + on + ")");
  }
  return {};
}

std::optional<std::string> Schema::declared_name(std::string_view attr, bool* rt) {
  if (attr.substr(0, 2) == "__") return std::nullopt;
  const bool on_rt = attr.substr(0, graph::kRtAttrPrefix.size()) == graph::kRtAttrPrefix;
  if (rt != nullptr) *rt = on_rt;
  return std::string(on_rt ? attr.substr(graph::kRtAttrPrefix.size()) : attr);
}

bool Schema::allows_type_change(graph::Symbol attr) const {
  const auto name = declared_name(attr.str());
  if (!name) return open_;  // the runtime's own: declared nowhere
  auto it = attributes_.find(*name);
  return it == attributes_.end() ? open_ : !it->second.type.has_value();
}

}  // namespace quiver::agents::inline rules::schema
