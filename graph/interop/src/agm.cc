// AGM XML worlds (<AGMModel>) to a plan, and the graph back to one.

#include "quiver/interop/agm.h"

#include <pugixml.hpp>

#include <algorithm>
#include <sstream>

#include "euler_xyz.h"
#include "export_view.h"
#include "plan.h"
#include "text_values.h"

namespace quiver::interop {
namespace {

using graph::Value;
using internal::Attrs;
using internal::malformed;
using internal::Plan;
using internal::in_quotes;

/// Lines of a text, found by byte offset (the file's line starts, binary-searched).
class Lines {
 public:
  explicit Lines(std::string_view text) {
    starts_.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts_.push_back(i + 1);
  }
  /// 1-based line and column of `offset`.
  std::pair<std::size_t, std::size_t> at(std::ptrdiff_t offset) const {
    const std::size_t o = offset < 0 ? 0 : static_cast<std::size_t>(offset);
    const auto it = std::upper_bound(starts_.begin(), starts_.end(), o);
    const std::size_t line = static_cast<std::size_t>(it - starts_.begin());
    return {line, o - starts_[line - 1] + 1};
  }

 private:
  std::vector<std::size_t> starts_;
};

/// Where an element is, for messages: `file:line: <tag a="1" b="2">`.
class Locator {
 public:
  Locator(std::string src, std::string_view text) : src_(std::move(src)), lines_(text) {}

  std::string at(const pugi::xml_node& e) const {
    std::string out = src_ + ":" + std::to_string(lines_.at(e.offset_debug()).first) + ": <" + e.name();
    for (const pugi::xml_attribute& a : e.attributes()) {
      std::string v = a.value();
      if (v.size() > 40) v = v.substr(0, 40) + "…";
      out += std::string(" ") + a.name() + "=\"" + v + "\"";
    }
    return out + ">";
  }

 private:
  std::string src_;
  Lines lines_;
};

/// An RT link's pose, as AGM's inner model reads it: tx ty tz (mm) rx ry rz (rad).
constexpr const char* kPoseKeys[] = {"tx", "ty", "tz", "rx", "ry", "rz"};

bool is_agm_pose_key(std::string_view key) {
  return std::find_if(std::begin(kPoseKeys), std::end(kPoseKeys), [&](const char* k) { return key == k; }) !=
         std::end(kPoseKeys);
}

/// AGM ids: digits are a number (AGM reads them with atoi: "05" is 5); anything else (the
/// variables of target models, "r", "obj1") is kept as written.
std::string canonical_id(const std::string& id) {
  std::uint64_t n;
  return internal::parse_uint64(id, n) ? std::to_string(n) : id;
}

/// The XML attributes an element must have; errors name the element.
Result<std::string> required(const pugi::xml_node& e, const char* name, const Locator& loc, bool non_empty = true) {
  pugi::xml_attribute a = e.attribute(name);
  if (!a) return malformed(loc.at(e), std::string("missing the attribute ") + name);
  std::string v = a.value();
  if (non_empty && v.empty()) return malformed(loc.at(e), std::string("the attribute ") + name + " is empty");
  return v;
}

void warn_unknown_attributes(const pugi::xml_node& e, std::initializer_list<const char*> known, const Locator& loc,
                             std::vector<std::string>& warnings) {
  for (const pugi::xml_attribute& a : e.attributes()) {
    const bool ok = std::any_of(known.begin(), known.end(), [&](const char* k) { return std::string_view(a.name()) == k; });
    if (!ok) warnings.push_back(loc.at(e) + ": the attribute " + a.name() + " is not part of AGM's format: ignored");
  }
}

/// The key/value children of a symbol (<attribute>) or a link (<linkAttribute>).
Result<std::vector<std::pair<std::string, std::string>>> key_values(const pugi::xml_node& e, const char* child,
                                                                    const Locator& loc,
                                                                    std::vector<std::string>& warnings) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const pugi::xml_node& c : e.children()) {
    if (c.type() != pugi::node_element) continue;
    if (std::string_view(c.name()) != child) {
      warnings.push_back(loc.at(c) + ": not part of <" + e.name() + "> in AGM's format (which reads <" + child +
                         ">): ignored");
      continue;
    }
    auto key = required(c, "key", loc);
    if (!key.ok()) return key.error();
    auto value = required(c, "value", loc, /*non_empty=*/false);
    if (!value.ok()) return value.error();
    warn_unknown_attributes(c, {"key", "value"}, loc, warnings);
    out.emplace_back(std::move(*key), std::move(*value));
  }
  return out;
}

Status read_symbol(const pugi::xml_node& e, const Locator& loc, Plan& plan) {
  internal::PlanNode node;
  node.where = loc.at(e);
  auto id = required(e, "id", loc);
  if (!id.ok()) return id.error();
  if ((*id)[0] == '-') return malformed(node.where, "AGM ids are not negative");
  node.id = canonical_id(*id);
  auto type = required(e, "type", loc);
  if (!type.ok()) return type.error();
  node.type = std::move(*type);
  warn_unknown_attributes(e, {"id", "type", "x", "y", "name"}, loc, plan.warnings);
  auto kv = key_values(e, "attribute", loc, plan.warnings);
  if (!kv.ok()) return kv.error();
  std::string im_name;
  for (auto& [key, value] : *kv) {
    if (key == "agm_id" || key == "agm_x" || key == "agm_y")
      return malformed(node.where, "the attribute " + in_quotes(key) + " is where Quiver keeps the symbol's " +
                                       (key == "agm_id" ? "id" : "position") + ": a file cannot set it");
    if (key == "imName") im_name = value;
    node.attrs.emplace_back(key, internal::typed_by_content(value));
  }
  // The node's name: the symbol's name attribute (DSR's tools and our exporter write it), else
  // imName (the name AGM's inner model knows it by), else <type>_<id>.
  node.name = e.attribute("name").value();
  if (node.name.empty()) node.name = im_name;
  node.attrs.emplace_back("agm_id", Value(node.id));
  for (const char* xy : {"x", "y"})
    if (pugi::xml_attribute a = e.attribute(xy))
      node.attrs.emplace_back(std::string("agm_") + xy, internal::typed_by_content(a.value()));
  const std::string at = node.where;
  if (!plan.add_node(std::move(node))) return malformed(at, "a second symbol with id " + canonical_id(*id));
  return {};
}

Status read_link(const pugi::xml_node& e, const Locator& loc, Plan& plan, double metres_per_unit) {
  const std::string where = loc.at(e);
  std::string ends[2];
  for (int k = 0; k < 2; ++k) {
    auto id = required(e, k == 0 ? "src" : "dst", loc);
    if (!id.ok()) return id.error();
    ends[k] = canonical_id(*id);
  }
  auto label = required(e, "label", loc);
  if (!label.ok()) return label.error();
  warn_unknown_attributes(e, {"src", "dst", "label"}, loc, plan.warnings);
  auto kv = key_values(e, "linkAttribute", loc, plan.warnings);
  if (!kv.ok()) return kv.error();
  const std::size_t* from = plan.find(ends[0]);
  const std::size_t* to = plan.find(ends[1]);
  if (!from || !to) return malformed(where, "no symbol with id " + (from ? ends[1] : ends[0]));
  Attrs attrs;
  if (*label == "RT") {
    // AGM's inner model reads tx ty tz rx ry rz (a missing one is 0); the rest is kept.
    std::array<double, 3> t{0, 0, 0}, r{0, 0, 0};
    for (auto& entry : *kv) {
      const std::string& key = entry.first;
      const std::string& value = entry.second;
      auto k = std::find_if(std::begin(kPoseKeys), std::end(kPoseKeys), [&](const char* n) { return key == n; });
      if (k == std::end(kPoseKeys)) {
        attrs.emplace_back(key, internal::typed_by_content(value));
        continue;
      }
      double d;
      if (!internal::parse_decimal(value, d, /*comma=*/true))
        return malformed(where, "<linkAttribute key=\"" + key + "\" value=\"" + value + "\">: expected a number (" +
                                    (k - kPoseKeys < 3 ? "millimetres" : "radians") + ")");
      (k - kPoseKeys < 3 ? t[k - kPoseKeys] : r[k - kPoseKeys - 3]) = d;
    }
    plan.rts.push_back({*from, *to, internal::pose_from_xyz(t, r, metres_per_unit), std::move(attrs), where});
    return {};
  }
  for (auto& [key, value] : *kv) attrs.emplace_back(key, internal::typed_by_content(value));
  plan.edges.push_back({*from, *to, *label, std::move(attrs), where});
  return {};
}

Result<Plan> read_plan(std::string_view text, const std::string& src, double metres_per_unit) {
  if (std::string why = internal::wrong_format(text, WorldFormat::kAgmXml); !why.empty())
    return make_error(ErrorCode::kMalformed, src + ": " + why);
  pugi::xml_document doc;
  pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    const auto [line, col] = Lines(text).at(parsed.offset);
    return make_error(ErrorCode::kMalformed, src + ":" + std::to_string(line) + ":" + std::to_string(col) +
                                                 ": XML syntax error: " + parsed.description());
  }
  const pugi::xml_node root = doc.document_element();
  const Locator loc(src, text);
  if (std::string_view(root.name()) != "AGMModel")
    return malformed(loc.at(root), "not an AGM world: the root element is not <AGMModel>");
  Plan plan;
  plan.is_link_pose_key = &is_agm_pose_key;
  std::vector<pugi::xml_node> links;
  for (const pugi::xml_node& e : root.children()) {
    if (e.type() != pugi::node_element) continue;
    const std::string_view name = e.name();
    if (name == "symbol") {
      if (Status s = read_symbol(e, loc, plan); !s.ok()) return s.error();
    } else if (name == "link") {
      links.push_back(e);  // after every symbol: a link may come before its symbols
    } else if (name != "comment") {
      plan.warnings.push_back(loc.at(e) + ": not part of AGM's format: ignored");
    }
  }
  for (const pugi::xml_node& e : links)
    if (Status s = read_link(e, loc, plan, metres_per_unit); !s.ok()) return s.error();
  return plan;
}

void add_key_value(pugi::xml_node parent, const char* element, const std::string& key, const std::string& value) {
  pugi::xml_node a = parent.append_child(element);
  a.append_attribute("key").set_value(key.c_str());
  a.append_attribute("value").set_value(value.c_str());
}

}  // namespace

Result<ImportReport> import_agm(graph::Graph& g, std::string_view text, std::string_view source,
                                const ImportOptions& options) {
  auto plan = read_plan(text, std::string(source), metres_per(options.unit));
  if (!plan.ok()) return plan.error();
  return internal::apply_plan(g, *plan, options);
}

Result<ImportReport> import_agm_file(graph::Graph& g, const std::string& path, const ImportOptions& options) {
  auto text = read_file("import_agm_file()", path);
  if (!text.ok()) return text.error();
  return import_agm(g, *text, path, options);
}

ExportResult export_agm(const graph::Graph& g, const ExportOptions& options) {
  internal::IdPolicy policy;
  policy.attr = "agm_id";
  policy.consumed = {"agm_x", "agm_y"};
  policy.what = "AGM id";
  policy.id_of = [](const Value& v) -> std::optional<std::string> {
    if (const auto* s = v.get_if<std::string>(); s && !s->empty() && (*s)[0] != '-') return canonical_id(*s);
    bool exact;
    std::string text = internal::value_text(v, exact);
    std::uint64_t n;
    if (internal::parse_uint64(text, n)) return std::to_string(n);
    return std::nullopt;
  };
  internal::ExportView view = internal::make_export_view(g, policy, metres_per(options.unit));
  ExportResult result;
  result.warnings = std::move(view.warnings);
  const graph::Symbol im_name = graph::Symbol::find("imName");

  pugi::xml_document doc;
  pugi::xml_node root = doc.append_child("AGMModel");
  auto text_of = [&](const graph::Value& v, const std::string& who) {
    bool exact;
    std::string t = internal::value_text(v, exact);
    if (!exact)
      result.warnings.push_back(who + ": " + graph::Value::article(v.type()) + " becomes the text " + in_quotes(t) +
                                " (AGM attributes are strings; it reads back as " +
                                graph::Value::article(internal::typed_by_content(t).type()) + ")");
    return t;
  };
  for (const internal::ExportNode& n : view.nodes) {
    pugi::xml_node s = root.append_child("symbol");
    s.append_attribute("id").set_value(n.file_id.c_str());
    s.append_attribute("type").set_value(n.type.c_str());
    for (const char* xy : {"x", "y"}) {
      const graph::Value* v = g.attr(n.id, graph::Symbol::find(std::string("agm_") + xy));
      if (v) s.append_attribute(xy).set_value(text_of(*v, "node " + in_quotes(n.name) + " agm_" + xy).c_str());
    }
    // The name import would give without a name attribute: imName, else <type>_<id>.
    std::string derived = n.type + "_" + n.file_id;
    if (const graph::Value* v = im_name.is_null() ? nullptr : g.attr(n.id, im_name)) {
      bool exact;
      std::string t = internal::value_text(*v, exact);
      if (!t.empty()) derived = t;
    }
    if (n.name != derived) s.append_attribute("name").set_value(n.name.c_str());
    for (const auto& [key, value] : n.attrs)
      add_key_value(s, "attribute", key, text_of(*value, "node " + in_quotes(n.name) + " attribute " + in_quotes(key)));
  }
  for (std::size_t i = 0; i < view.nodes.size(); ++i) {
    const internal::ExportNode& n = view.nodes[i];
    // Its RT link first (from its parent), then its symbolic links.
    if (n.parent) {
      pugi::xml_node l = root.append_child("link");
      l.append_attribute("src").set_value(view.nodes[*n.parent].file_id.c_str());
      l.append_attribute("dst").set_value(n.file_id.c_str());
      l.append_attribute("label").set_value("RT");
      for (int k = 0; k < 6; ++k)
        add_key_value(l, "linkAttribute", kPoseKeys[k], internal::pose_text(k < 3 ? n.t[k] : n.r[k - 3]));
      for (const auto& [key, value] : n.rt_attrs) {
        if (is_agm_pose_key(key)) {
          result.warnings.push_back("node " + in_quotes(n.name) + " attribute " + in_quotes("rt:" + key) +
                                    ": the RT link's pose goes there: not written");
          continue;
        }
        add_key_value(l, "linkAttribute", key, text_of(*value, "node " + in_quotes(n.name) + " attribute " + in_quotes("rt:" + key)));
      }
    }
  }
  for (const internal::ExportEdge& e : view.edges) {
    pugi::xml_node l = root.append_child("link");
    l.append_attribute("src").set_value(view.nodes[e.from].file_id.c_str());
    l.append_attribute("dst").set_value(view.nodes[e.to].file_id.c_str());
    l.append_attribute("label").set_value(e.type.c_str());
    for (const auto& [key, value] : e.attrs)
      add_key_value(l, "linkAttribute", key,
                    text_of(*value, "edge " + in_quotes(view.nodes[e.from].name) + " -> " + in_quotes(view.nodes[e.to].name) +
                                        " (" + e.type + ") attribute " + in_quotes(key)));
  }
  std::ostringstream out;
  doc.save(out, "\t", pugi::format_default | pugi::format_no_declaration, pugi::encoding_utf8);
  result.text = out.str();
  return result;
}

Result<ExportResult> export_agm_file(const graph::Graph& g, const std::string& path, const ExportOptions& options) {
  ExportResult r = export_agm(g, options);
  if (Status s = write_file("export_agm_file()", path, r.text); !s.ok()) return s.error();
  return r;
}

}  // namespace quiver::interop
