// CORTEX DSR JSON worlds read: every layout in use (symbols keyed by id or in an array, links
// inside symbols or at the top), checked, to a plan the graph applies.

#include "quiver/interop/dsr.h"

#include "dsr_json.h"
#include "plan.h"
#include "quiver/base/text_position.h"
#include "text_values.h"

namespace quiver::interop {
namespace {

using graph::Value;
using internal::Attrs;
using internal::convert;
using internal::json;
using internal::malformed;
using internal::node_id;
using internal::Plan;
using internal::in_quotes;
using internal::raw_attributes;
using internal::RawAttr;
using internal::rt_pose;
using internal::token;

struct PendingLink {
  const json* link;
  std::string where;
};

Status read_symbol(const json& s, const std::string& where, const std::string* key, Plan& plan,
                   std::vector<PendingLink>& links) {
  if (!s.is_object()) return malformed(where, "expected a symbol object");
  internal::PlanNode node;
  node.where = where;
  auto id = s.find("id");
  if (id == s.end() && !key) return malformed(where, "missing \"id\"");
  auto text = node_id(id != s.end() ? *id : json(*key), id != s.end() ? where + "/id" : where);
  if (!text.ok()) return text.error();
  node.id = *text;
  if (key && id != s.end()) {
    auto key_id = node_id(json(*key), where);
    if (!key_id.ok() || *key_id != node.id)
      plan.warnings.push_back(where + ": the symbol's key " + in_quotes(*key) + " is not its id " + node.id + ": the id counts");
  }
  auto type = s.find("type");
  if (type == s.end() || !type->is_string() || type->get_ref<const std::string&>().empty())
    return malformed(type == s.end() ? where : where + "/type", "expected the symbol's \"type\" (a non-empty string)");
  node.type = type->get<std::string>();
  if (auto name = s.find("name"); name != s.end() && !name->is_null()) {
    if (!name->is_string()) return malformed(where + "/name", "expected a string");
    node.name = name->get<std::string>();
  }
  for (auto it = s.begin(); it != s.end(); ++it)
    if (it.key() != "id" && it.key() != "type" && it.key() != "name" && it.key() != "attribute" && it.key() != "links")
      plan.warnings.push_back(where + "/" + token(it.key()) + ": not part of a CORTEX symbol: ignored");
  if (auto a = s.find("attribute"); a != s.end()) {
    auto raw = raw_attributes(*a, where + "/attribute");
    if (!raw.ok()) return raw.error();
    auto attrs = convert(*raw, plan.warnings);
    if (!attrs.ok()) return attrs.error();
    node.attrs = std::move(*attrs);
  }
  for (const auto& [name, value] : node.attrs)
    if (name == "dsr_id")
      return malformed(where + "/attribute/dsr_id", "\"dsr_id\" is where Quiver keeps the CORTEX id: a file cannot set it");
  node.attrs.emplace_back("dsr_id", Value(std::stoull(node.id)));
  if (auto l = s.find("links"); l != s.end() && !l->is_null()) {
    if (!l->is_array()) return malformed(where + "/links", "expected an array of links");
    for (std::size_t i = 0; i < l->size(); ++i) links.push_back({&(*l)[i], where + "/links/" + std::to_string(i)});
  }
  const std::string at = node.where;
  if (!plan.add_node(std::move(node))) return malformed(at, "a second symbol with id " + *text);
  return {};
}

Status read_link(const PendingLink& p, Plan& plan, double metres_per_unit) {
  const json& l = *p.link;
  if (!l.is_object()) return malformed(p.where, "expected a link {\"src\", \"dst\", \"label\", \"linkAttribute\"}");
  std::string ends[2];
  for (int k = 0; k < 2; ++k) {
    const char* field = k == 0 ? "src" : "dst";
    auto f = l.find(field);
    if (f == l.end()) return malformed(p.where, std::string("missing \"") + field + "\"");
    auto id = node_id(*f, p.where + "/" + field);
    if (!id.ok()) return id.error();
    ends[k] = *id;
  }
  auto label = l.find("label");
  if (label == l.end() || !label->is_string() || label->get_ref<const std::string&>().empty())
    return malformed(label == l.end() ? p.where : p.where + "/label", "expected the link's \"label\" (a non-empty string)");
  const std::string type = label->get<std::string>();
  std::vector<RawAttr> raw;
  if (auto a = l.find("linkAttribute"); a != l.end()) {
    auto r = raw_attributes(*a, p.where + "/linkAttribute");
    if (!r.ok()) return r.error();
    raw = std::move(*r);
  }
  const std::size_t* from = plan.find(ends[0]);
  const std::size_t* to = plan.find(ends[1]);
  if (!from || !to) {
    // CORTEX skips such a link with a warning, and so do we (options.strict refuses the file).
    plan.warnings.push_back(p.where + ": no symbol with id " + (from ? ends[1] : ends[0]) + ": the link " +
                            in_quotes(type) + " is skipped");
    return {};
  }
  if (type == "RT") {
    auto pose = rt_pose(std::move(raw), p.where, plan.warnings, metres_per_unit);
    if (!pose.ok()) return pose.error();
    auto attrs = convert(pose->rest, plan.warnings);
    if (!attrs.ok()) return attrs.error();
    plan.rts.push_back({*from, *to, pose->pose, std::move(*attrs), p.where});
    return {};
  }
  auto attrs = convert(raw, plan.warnings);
  if (!attrs.ok()) return attrs.error();
  plan.edges.push_back({*from, *to, type, std::move(*attrs), p.where});
  return {};
}

Result<json> parse_json(std::string_view text, const std::string& src) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    auto pos = msg.find("; ");  // drop nlohmann's "[json.exception...] parse error at line..." prefix
    std::string why = pos == std::string::npos ? msg : msg.substr(pos + 2);
    return make_error(ErrorCode::kMalformed,
                      src + ":" + line_col(text, e.byte == 0 ? 0 : e.byte - 1) + ": JSON syntax error: " + why);
  } catch (const json::exception& e) {
    std::string msg = e.what();
    auto pos = msg.find("] ");
    return make_error(ErrorCode::kMalformed, src + ": JSON error: " + (pos == std::string::npos ? msg : msg.substr(pos + 2)));
  }
}

Result<Plan> read_plan(std::string_view text, const std::string& src, const ImportOptions& options) {
  if (std::string why = internal::wrong_format(text, WorldFormat::kDsrJson); !why.empty())
    return make_error(ErrorCode::kMalformed, src + ": " + why);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // Qt reads files with a BOM
  auto root = parse_json(text, src);
  if (!root.ok()) return root.error();
  if (!root->is_object() || !root->contains("DSRModel"))
    return malformed(src + ":/", "not a CORTEX DSR world: no \"DSRModel\" object at the top");
  const json& model = (*root)["DSRModel"];
  const std::string base = src + ":/DSRModel";
  if (!model.is_object()) return malformed(base, "expected an object");
  if (model.contains("symbols") && model.contains("symbol"))
    return malformed(base, "both \"symbols\" and \"symbol\": give one");
  Plan plan;
  plan.is_link_pose_key = &internal::is_pose_key;
  for (auto it = model.begin(); it != model.end(); ++it)
    if (it.key() != "symbols" && it.key() != "symbol" && it.key() != "link")
      plan.warnings.push_back(base + "/" + token(it.key()) + ": not part of a CORTEX world: ignored");
  std::vector<PendingLink> links;
  const char* member = model.contains("symbol") ? "symbol" : "symbols";
  if (auto s = model.find(member); s != model.end() && !s->is_null()) {
    const std::string where = base + "/" + member;
    if (s->is_object()) {
      for (auto it = s->begin(); it != s->end(); ++it)
        if (Status st = read_symbol(it.value(), where + "/" + token(it.key()), &it.key(), plan, links); !st.ok())
          return st.error();
    } else if (s->is_array()) {
      for (std::size_t i = 0; i < s->size(); ++i)
        if (Status st = read_symbol((*s)[i], where + "/" + std::to_string(i), nullptr, plan, links); !st.ok())
          return st.error();
    } else {
      return malformed(where, "expected an object of symbols keyed by id (or an array of symbols)");
    }
  }
  if (auto l = model.find("link"); l != model.end() && !l->is_null()) {
    if (!l->is_array()) return malformed(base + "/link", "expected an array of links");
    for (std::size_t i = 0; i < l->size(); ++i) links.push_back({&(*l)[i], base + "/link/" + std::to_string(i)});
  }
  for (const PendingLink& p : links)
    if (Status st = read_link(p, plan, metres_per(options.unit)); !st.ok()) return st.error();
  return plan;
}

}  // namespace

Result<ImportReport> import_dsr(graph::Graph& g, std::string_view text, std::string_view source,
                                const ImportOptions& options) {
  const std::string src(source);
  auto plan = read_plan(text, src, options);
  if (!plan.ok()) return plan.error();
  return internal::apply_plan(g, *plan, options);
}

Result<ImportReport> import_dsr_file(graph::Graph& g, const std::string& path, const ImportOptions& options) {
  auto text = read_file("import_dsr_file()", path);
  if (!text.ok()) return text.error();
  return import_dsr(g, *text, path, options);
}

}  // namespace quiver::interop
