// CORTEX DSR JSON worlds written: the graph in the current layout (symbols keyed by id, links
// inside their source symbol, values with their type codes, RT links as Euler XYZ poses).

#include "quiver/interop/dsr.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "dsr_json.h"
#include "export_view.h"
#include "plan.h"
#include "quiver/graph/limits.h"
#include "text_values.h"

namespace quiver::interop {
namespace {

using graph::Value;
using graph::ValueType;
using internal::is_pose_key;
using internal::json;
using internal::in_quotes;

/// A float as JSON: the double its shortest text reads as ("0.1", not 0.10000000149011612).
json float_json(float f) { return internal::read_back(internal::shortest(f)); }

/// A double as a float, clamped to the float range (`changed` tells).
float to_float(double d, bool& changed) {
  if (std::fabs(d) > FLT_MAX) {
    changed = true;
    return d > 0 ? FLT_MAX : -FLT_MAX;
  }
  return static_cast<float>(d);
}

/// Values JSON cannot hold (NaN, infinities) are written as 0.
double finite(double d, bool& changed) {
  if (std::isfinite(d)) return d;
  changed = true;
  return 0.0;
}

template <class Vec>
json floats_json(const Vec& v, bool& changed) {
  json a = json::array();
  for (float f : v) a.push_back(float_json(static_cast<float>(finite(f, changed))));
  return a;
}

/// A value with its CORTEX type code. `note` receives what was changed to fit, if anything.
json code_and_value(const Value& v, std::string& note) {
  int code = 0;
  json value;
  bool changed = false;
  switch (v.type()) {
    case ValueType::kString: {
      const std::string& s = *v.get_if<std::string>();
      if (!graph::valid_utf8(s)) note = "text that is not UTF-8 (JSON holds only UTF-8): invalid bytes replaced";
      value = s;
      break;
    }
    case ValueType::kInt32:
      code = 1;
      value = *v.get_if<std::int32_t>();
      break;
    case ValueType::kFloat:
      code = 2;
      value = float_json(static_cast<float>(finite(*v.get_if<float>(), changed)));
      break;
    case ValueType::kFloatVec:
      code = 3;
      value = floats_json(*v.get_if<graph::FloatVec>(), changed);
      break;
    case ValueType::kBool:
      code = 4;
      value = *v.get_if<bool>();
      break;
    case ValueType::kBytes:
      code = 5;
      value = json::array();
      for (std::uint8_t b : *v.get_if<graph::Bytes>()) value.push_back(b);
      break;
    case ValueType::kUInt32:
      code = 6;
      value = *v.get_if<std::uint32_t>();
      break;
    case ValueType::kUInt64:
      code = 7;
      value = std::to_string(*v.get_if<std::uint64_t>());  // as CORTEX writes it
      break;
    case ValueType::kDouble:
      code = 8;
      value = finite(*v.get_if<double>(), changed);
      break;
    case ValueType::kUInt64Vec:
      code = 9;
      value = json::array();
      for (std::uint64_t x : *v.get_if<graph::UInt64Vec>()) value.push_back(std::to_string(x));
      break;
    case ValueType::kVec2f:
      code = 10;
      value = floats_json(*v.get_if<graph::Vec2f>(), changed);
      break;
    case ValueType::kVec3f:
      code = 11;
      value = floats_json(*v.get_if<graph::Vec3f>(), changed);
      break;
    case ValueType::kVec4f:
      code = 12;
      value = floats_json(*v.get_if<graph::Vec4f>(), changed);
      break;
    case ValueType::kVec6f:
      code = 13;
      value = floats_json(*v.get_if<graph::Vec6f>(), changed);
      break;
    case ValueType::kInt64: {
      const std::int64_t i = *v.get_if<std::int64_t>();
      if (i >= INT32_MIN && i <= INT32_MAX) {
        code = 1;
        value = i;
        note = "an int64 (CORTEX has no int64): written as an int32 (type code 1)";
      } else if (i >= 0) {
        code = 7;
        value = std::to_string(i);
        note = "an int64 (CORTEX has no int64): written as a uint64 (type code 7)";
      } else {
        code = 8;
        value = static_cast<double>(i);
        note = "an int64 (CORTEX has no int64): written as a double (type code 8)";
      }
      break;
    }
    case ValueType::kDoubleVec:
    case ValueType::kMat4d: {
      code = 3;
      value = json::array();
      const auto& d = v.type() == ValueType::kMat4d ? graph::DoubleVec(v.get_if<graph::Mat4d>()->m.begin(),
                                                                       v.get_if<graph::Mat4d>()->m.end())
                                                    : *v.get_if<graph::DoubleVec>();
      for (double x : d) value.push_back(float_json(to_float(finite(x, changed), changed)));
      note = std::string("a ") + graph::to_string(v.type()) +
             " (CORTEX has no vector of doubles): written as a float vector (type code 3)";
      break;
    }
  }
  if (changed)
    note += std::string(note.empty() ? "" : "; ") +
            "not finite or beyond the float range: written as 0 or the largest float (JSON has no NaN or infinity)";
  json out = json::object();
  out["type"] = code;
  out["value"] = std::move(value);
  return out;
}

json vector_json(const std::array<double, 3>& v) {
  json a = json::array();
  for (double x : v) a.push_back(internal::read_back(internal::pose_text(x)));
  return a;
}

}  // namespace

ExportResult export_dsr(const graph::Graph& g, const ExportOptions& options) {
  internal::IdPolicy policy;
  policy.attr = "dsr_id";
  policy.what = "CORTEX id";
  policy.id_of = [](const Value& v) -> std::optional<std::string> {
    if (const auto* u = v.get_if<std::uint64_t>()) return std::to_string(*u);
    if (const auto* i = v.get_if<std::int64_t>(); i && *i >= 0) return std::to_string(*i);
    if (const auto* i = v.get_if<std::int32_t>(); i && *i >= 0) return std::to_string(*i);
    if (const auto* u = v.get_if<std::uint32_t>()) return std::to_string(*u);
    std::uint64_t x;
    if (const auto* s = v.get_if<std::string>(); s && internal::parse_uint64(*s, x)) return std::to_string(x);
    return std::nullopt;
  };
  internal::ExportView view = internal::make_export_view(g, policy, metres_per(options.unit));
  ExportResult result;
  result.warnings = std::move(view.warnings);
  auto warn = [&](const std::string& what, const std::string& note) {
    if (!note.empty()) result.warnings.push_back(what + ": " + note);
  };

  // Each node's outgoing links: its symbolic edges and the RT links to its children, by target.
  std::vector<std::vector<std::size_t>> children(view.nodes.size());
  for (std::size_t i = 0; i < view.nodes.size(); ++i)
    if (view.nodes[i].parent) children[*view.nodes[i].parent].push_back(i);

  json symbols = json::object();
  for (std::size_t i = 0; i < view.nodes.size(); ++i) {
    const internal::ExportNode& n = view.nodes[i];
    const std::string who = "node " + in_quotes(n.name);
    json attrs = json::object();
    bool has_level = false, has_parent = false;
    for (const auto& [name, value] : n.attrs) {
      std::string note;
      attrs[name] = code_and_value(*value, note);
      warn(who + " attribute " + in_quotes(name), note);
      has_level |= name == "level";
      has_parent |= name == "parent";
    }
    if (!n.own_id) {
      // CORTEX finds a node's RT parent by its `parent` attribute and needs `level` to add RT
      // links: a node made in Quiver gets them (a node from a CORTEX file has what it had).
      if (!has_level) attrs["level"] = json{{"type", 1}, {"value", n.depth}};
      if (n.parent && !has_parent) attrs["parent"] = json{{"type", 7}, {"value", view.nodes[*n.parent].file_id}};
    }
    json sorted_attrs = json::object();  // attributes by name, as CORTEX writes them
    std::vector<std::string> keys;
    for (auto it = attrs.begin(); it != attrs.end(); ++it) keys.push_back(it.key());
    std::sort(keys.begin(), keys.end());
    for (const std::string& k : keys) sorted_attrs[k] = attrs[k];

    struct Out {
      std::size_t to;
      std::string label;
      json link;
    };
    std::vector<Out> out;
    for (std::size_t e : n.edges) {
      const internal::ExportEdge& edge = view.edges[e];
      json la = json::object();
      for (const auto& [name, value] : edge.attrs) {
        std::string note;
        la[name] = code_and_value(*value, note);
        warn("edge " + in_quotes(n.name) + " -> " + in_quotes(view.nodes[edge.to].name) + " (" + edge.type + ") attribute " +
                 in_quotes(name),
             note);
      }
      out.push_back({edge.to, edge.type,
                     json{{"dst", view.nodes[edge.to].file_id}, {"label", edge.type}, {"linkAttribute", std::move(la)},
                          {"src", n.file_id}}});
    }
    for (std::size_t c : children[i]) {
      const internal::ExportNode& child = view.nodes[c];
      json la = json::object();
      for (const auto& [name, value] : child.rt_attrs) {
        if (is_pose_key(name)) {
          result.warnings.push_back("node " + in_quotes(child.name) + " attribute " + in_quotes("rt:" + name) +
                                    ": the RT link's pose goes there: not written");
          continue;
        }
        std::string note;
        la[name] = code_and_value(*value, note);
        warn("node " + in_quotes(child.name) + " attribute " + in_quotes("rt:" + name), note);
      }
      la["rt_rotation_euler_xyz"] = json{{"type", 3}, {"value", vector_json(child.r)}};
      la["rt_translation"] = json{{"type", 3}, {"value", vector_json(child.t)}};
      out.push_back({c, "RT",
                     json{{"dst", child.file_id}, {"label", "RT"}, {"linkAttribute", std::move(la)}, {"src", n.file_id}}});
    }
    std::sort(out.begin(), out.end(), [](const Out& a, const Out& b) { return a.to != b.to ? a.to < b.to : a.label < b.label; });
    json links = json::array();
    for (Out& o : out) links.push_back(std::move(o.link));

    json sym = json::object();
    sym["attribute"] = std::move(sorted_attrs);
    sym["id"] = n.file_id;
    sym["links"] = std::move(links);
    sym["name"] = n.name;
    sym["type"] = n.type;
    symbols[n.file_id] = std::move(sym);
  }
  json root = json::object();
  root["DSRModel"]["symbols"] = std::move(symbols);
  result.text = root.dump(4, ' ', false, json::error_handler_t::replace) + "\n";
  return result;
}

Result<ExportResult> export_dsr_file(const graph::Graph& g, const std::string& path, const ExportOptions& options) {
  ExportResult r = export_dsr(g, options);
  if (Status s = write_file("export_dsr_file()", path, r.text); !s.ok()) return s.error();
  return r;
}

}  // namespace quiver::interop
