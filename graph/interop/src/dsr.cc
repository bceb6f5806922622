// CORTEX DSR JSON worlds: every layout in use, to a plan; the graph back to the current layout.

#include "quiver/interop/dsr.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "euler_xyz.h"
#include "export_view.h"
#include "plan.h"
#include "quiver/graph/limits.h"
#include "quiver/base/text_position.h"
#include "text_values.h"

namespace quiver::interop {
namespace {

using json = nlohmann::ordered_json;
using graph::Value;
using graph::ValueType;
using internal::Attrs;
using internal::malformed;
using internal::Plan;
using internal::in_quotes;

/// A JSON pointer's reference token (RFC 6901: '~' as ~0, '/' as ~1).
std::string token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

// ------------------------------------------------------------------------------ JSON numbers

/// A number or a decimal string (',' accepted as the decimal point, as CORTEX's reader does).
bool as_double(const json& j, double& out) {
  if (j.is_number()) {
    out = j.get<double>();
    return std::isfinite(out);
  }
  return j.is_string() && internal::parse_decimal(j.get_ref<const std::string&>(), out, /*comma=*/true);
}

/// An integer, a number with a fraction (rounded, like Qt's QVariant::toInt; `rounded` tells),
/// or the same as a string.
bool as_integer(const json& j, std::int64_t& out, bool& rounded) {
  rounded = false;
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(INT64_MAX)) return false;
    out = static_cast<std::int64_t>(u);
    return true;
  }
  if (j.is_number_integer()) {
    out = j.get<std::int64_t>();
    return true;
  }
  if (j.is_string() && internal::parse_int64(j.get_ref<const std::string&>(), out)) return true;
  double d;
  if (!as_double(j, d) || std::fabs(d) > 9.0e18) return false;
  out = std::llround(d);
  rounded = static_cast<double>(out) != d;
  return true;
}

/// A non-negative integer, or digits in a string (CORTEX writes uint64 values as strings).
bool as_uint64(const json& j, std::uint64_t& out) {
  if (j.is_number_unsigned()) {
    out = j.get<std::uint64_t>();
    return true;
  }
  if (j.is_number_integer()) {
    const auto i = j.get<std::int64_t>();
    if (i < 0) return false;
    out = static_cast<std::uint64_t>(i);
    return true;
  }
  return j.is_string() && internal::parse_uint64(j.get_ref<const std::string&>(), out);
}

bool float_range(double d) { return std::fabs(d) <= FLT_MAX; }

/// The numbers of an array (numbers or numeric strings), or of a string of numbers separated by
/// white space (the oldest files).
bool as_doubles(const json& j, std::vector<double>& out) {
  out.clear();
  if (j.is_array()) {
    out.reserve(j.size());
    for (const json& e : j) {
      double d;
      if (!as_double(e, d)) return false;
      out.push_back(d);
    }
    return true;
  }
  if (!j.is_string()) return false;
  const std::string& s = j.get_ref<const std::string&>();
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) ++i;
    std::size_t k = i;
    while (k < s.size() && s[k] != ' ' && s[k] != '\t' && s[k] != '\n' && s[k] != '\r') ++k;
    if (k == i) break;
    double d;
    if (!internal::parse_decimal(std::string_view(s).substr(i, k - i), d, true)) return false;
    out.push_back(d);
    i = k;
  }
  return true;
}

template <std::size_t N>
bool as_floats(const json& j, std::array<float, N>& out) {
  std::vector<double> d;
  if (!as_doubles(j, d) || d.size() != N) return false;
  for (std::size_t i = 0; i < N; ++i) {
    if (!float_range(d[i])) return false;
    out[i] = static_cast<float>(d[i]);
  }
  return true;
}

// ------------------------------------------------------------------------------ values

constexpr int kCodes = 14;  // 0 string ... 13 vec6f (dsr.h)

/// The value of an attribute with a CORTEX type code. `warn` receives notes (rounding).
Result<Value> typed_value(int code, const json& v, const std::string& where, std::vector<std::string>& warnings) {
  auto bad = [&](const std::string& expect) {
    return malformed(where, "type code " + std::to_string(code) + " expects " + expect);
  };
  // Codes 10 to 13: std::array<float, N>.
  auto fixed = [&]<std::size_t N>() -> Result<Value> {
    std::array<float, N> f;
    if (!as_floats(v, f)) return bad("an array of " + std::to_string(N) + " numbers");
    return Value(f);
  };
  switch (code) {
    case 0:
      if (v.is_string()) return Value(v.get<std::string>());
      if (v.is_number() || v.is_boolean()) return Value(v.dump());  // Qt's toString()
      return bad("a string");
    case 1:
    case 6: {
      std::int64_t i;
      bool rounded;
      if (!as_integer(v, i, rounded)) return bad("an integer");
      if (code == 1) {
        if (i < INT32_MIN || i > INT32_MAX) return bad("an integer in int32 range");
        if (rounded) warnings.push_back(where + ": " + v.dump() + " is not an integer: rounded to " + std::to_string(i));
        return Value::int32(static_cast<std::int32_t>(i));
      }
      // CORTEX writes a uint32 as the int32 of the same bits: a negative value wraps.
      if (i < INT32_MIN || i > static_cast<std::int64_t>(UINT32_MAX)) return bad("an integer in uint32 range");
      if (rounded) warnings.push_back(where + ": " + v.dump() + " is not an integer: rounded to " + std::to_string(i));
      return Value::uint32(static_cast<std::uint32_t>(i < 0 ? i + (std::int64_t{1} << 32) : i));
    }
    case 2: {
      double d;
      if (!as_double(v, d) || !float_range(d)) return bad("a number in float range");
      return Value(static_cast<float>(d));
    }
    case 3: {
      std::vector<double> d;
      if (!as_doubles(v, d)) return bad("an array of numbers");
      graph::FloatVec f;
      f.reserve(d.size());
      for (double x : d) {
        if (!float_range(x)) return bad("an array of numbers in float range");
        f.push_back(static_cast<float>(x));
      }
      return Value(std::move(f));
    }
    case 4:
      if (v.is_boolean()) return Value(v.get<bool>());
      if (v.is_number_integer() && (v.get<std::int64_t>() == 0 || v.get<std::int64_t>() == 1))
        return Value(v.get<std::int64_t>() == 1);
      if (v.is_string()) {
        std::string s = v.get<std::string>();
        for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (s == "true" || s == "1") return Value(true);
        if (s == "false" || s == "0") return Value(false);
      }
      return bad("true or false");
    case 5: {
      if (!v.is_array()) return bad("an array of bytes (0 to 255)");
      graph::Bytes b;
      b.reserve(v.size());
      for (const json& e : v) {
        std::uint64_t x;
        if (!as_uint64(e, x) || x > 255) return bad("an array of bytes (0 to 255)");
        b.push_back(static_cast<std::uint8_t>(x));
      }
      return Value(std::move(b));
    }
    case 7: {
      std::uint64_t x;
      if (!as_uint64(v, x)) return bad("an unsigned integer (or its digits as a string)");
      return Value(x);
    }
    case 8: {
      double d;
      if (!as_double(v, d)) return bad("a number");
      return Value(d);
    }
    case 9: {
      if (!v.is_array()) return bad("an array of unsigned integers");
      graph::UInt64Vec u;
      u.reserve(v.size());
      for (const json& e : v) {
        std::uint64_t x;
        if (!as_uint64(e, x)) return bad("an array of unsigned integers");
        u.push_back(x);
      }
      return Value(std::move(u));
    }
    case 10: return fixed.template operator()<2>();
    case 11: return fixed.template operator()<3>();
    case 12: return fixed.template operator()<4>();
    case 13: return fixed.template operator()<6>();
  }
  return malformed(where, "unknown type code " + std::to_string(code));
}

/// A value without a type code, typed by its content with CORTEX's types: an integer is an int32
/// (a uint64 beyond it; a double below it), a number with a fraction a double, true/false a bool,
/// an array of numbers a float_vec; a string is read as AGM's strings are (an integer, a decimal
/// number or true/false in it take those types), else stays a string.
Result<Value> untyped_value(const json& v, const std::string& where) {
  auto integer = [](std::int64_t i) -> Value {
    if (i >= INT32_MIN && i <= INT32_MAX) return Value::int32(static_cast<std::int32_t>(i));
    if (i >= 0) return Value(static_cast<std::uint64_t>(i));
    return Value(static_cast<double>(i));
  };
  if (v.is_boolean()) return Value(v.get<bool>());
  if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))
    return Value(v.get<std::uint64_t>());
  if (v.is_number_integer()) return integer(v.get<std::int64_t>());
  if (v.is_number_float()) return Value(v.get<double>());
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    std::uint64_t u;
    if (internal::parse_uint64(s, u) && u > static_cast<std::uint64_t>(INT64_MAX)) return Value(u);
    Value typed = internal::typed_by_content(s);
    if (const auto* i = typed.get_if<std::int64_t>()) {
      if (*i < INT32_MIN && *i >= -(std::int64_t{1} << 53)) return Value(static_cast<double>(*i));
      if (*i < INT32_MIN) return Value(s);
      return integer(*i);
    }
    return typed;
  }
  if (v.is_array()) {
    std::vector<double> d;
    if (as_doubles(v, d) && std::all_of(d.begin(), d.end(), float_range))
      return Value(graph::FloatVec(d.begin(), d.end()));
  }
  return malformed(where, "expected a value (a string, number, bool or array of numbers)");
}

/// A type code: a number or its digits as a string.
Result<int> type_code(const json& t, const std::string& where) {
  std::int64_t code = -1;
  if (t.is_number_integer()) code = t.get<std::int64_t>();
  else if (t.is_string() && !internal::parse_int64(t.get_ref<const std::string&>(), code)) code = -1;
  if (code < 0 || code >= kCodes)
    return malformed(where, "unknown type code " + t.dump() + " (CORTEX's codes are 0 to 13)");
  return static_cast<int>(code);
}

/// One attribute: {"type": CODE, "value": V}, or {"value": V} without a code.
Result<Value> attribute_value(const json& a, const std::string& where, std::vector<std::string>& warnings) {
  auto value = a.find("value");
  if (value == a.end()) return malformed(where, "missing \"value\"");
  auto type = a.find("type");
  if (type == a.end() || type->is_null()) return untyped_value(*value, where);
  auto code = type_code(*type, where);
  if (!code.ok()) return code.error();
  return typed_value(*code, *value, where, warnings);
}

/// One attribute entry with its name and where it is, before conversion (RT links read some of
/// them as poses).
struct RawAttr {
  std::string name;
  json entry;  ///< {"value": V[, "type": CODE]} (array entries also hold their "key")
  std::string where;
};

/// The entries of an "attribute" / "linkAttribute" member: an object name -> {type, value}
/// (with the hand-written {"key": NAME, "value": V} pair of the planner's example worlds), or an
/// array of {"key", "value"[, "type"]}.
Result<std::vector<RawAttr>> raw_attributes(const json& j, const std::string& where) {
  std::vector<RawAttr> out;
  if (j.is_null()) return out;
  if (j.is_object()) {
    const bool key_value_pair = j.contains("key") && j["key"].is_string() && j.contains("value") && !j["value"].is_object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string at = where + "/" + token(it.key());
      if (key_value_pair && (it.key() == "key" || it.key() == "value")) {
        if (it.key() == "key") out.push_back(RawAttr{it.value().get<std::string>(), json{{"value", j["value"]}}, where});
        continue;
      }
      if (!it.value().is_object()) return malformed(at, "expected {\"type\": CODE, \"value\": V}");
      out.push_back(RawAttr{it.key(), it.value(), at});
    }
    return out;
  }
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string at = where + "/" + std::to_string(i);
      const json& e = j[i];
      auto key = e.is_object() ? e.find("key") : e.end();
      if (!e.is_object() || key == e.end() || !key->is_string())
        return malformed(at, "expected {\"key\": NAME, \"value\": V[, \"type\": CODE]}");
      out.push_back(RawAttr{key->get<std::string>(), e, at});
    }
    return out;
  }
  return malformed(where, "expected an object of attributes (or an array of {\"key\", \"value\"})");
}

Result<Attrs> convert(const std::vector<RawAttr>& raw, std::vector<std::string>& warnings) {
  Attrs out;
  out.reserve(raw.size());
  for (const RawAttr& a : raw) {
    if (a.name.empty()) return malformed(a.where, "an attribute with an empty name");
    auto v = attribute_value(a.entry, a.where, warnings);
    if (!v.ok()) return v.error();
    out.emplace_back(a.name, std::move(*v));
  }
  return out;
}

/// A CORTEX id: digits in a string or an unsigned number, as canonical decimal text.
Result<std::string> node_id(const json& j, const std::string& where) {
  std::uint64_t id;
  if (!as_uint64(j, id)) return malformed(where, "expected a CORTEX id (an unsigned integer)");
  return std::to_string(id);
}

// ------------------------------------------------------------------------------ RT links

/// The pose of an RT link, from whichever form it has, and its other attributes.
struct RtPose {
  graph::Pose pose;
  std::vector<RawAttr> rest;
};

Result<RtPose> rt_pose(std::vector<RawAttr> raw, const std::string& where, std::vector<std::string>& warnings,
                       double metres_per_unit) {
  struct Form {
    const char* translation;
    const char* rotation;
  };
  static constexpr Form kForms[] = {{"rt_translation", "rt_rotation_euler_xyz"},
                                    {"translation", "rotation_euler_xyz"},
                                    {"trans", "rot"}};
  static constexpr const char* kScalars[] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  const RawAttr* vec[2] = {nullptr, nullptr};
  const Form* form = nullptr;
  const RawAttr* scalar[6] = {};
  const RawAttr* stamps = nullptr;
  const RawAttr* head = nullptr;
  RtPose out;
  for (const RawAttr& a : raw) {
    bool used = false;
    for (const Form& f : kForms) {
      for (int k = 0; k < 2; ++k) {
        if (a.name != (k == 0 ? f.translation : f.rotation)) continue;
        if (form && form != &f)
          return malformed(a.where, std::string("the RT link gives its pose twice (\"") + form->translation + "\" and \"" +
                                        a.name + "\")");
        form = &f;
        vec[k] = &a;
        used = true;
      }
    }
    for (int k = 0; k < 6; ++k)
      if (a.name == kScalars[k]) scalar[k] = &a, used = true;
    if (a.name == "rt_timestamps") stamps = &a, used = true;
    if (a.name == "rt_head_index") head = &a, used = true;
    if (!used) out.rest.push_back(a);
  }
  const bool any_scalar = std::any_of(std::begin(scalar), std::end(scalar), [](const RawAttr* a) { return a; });
  if (form && any_scalar)
    return malformed(where, std::string("the RT link gives its pose twice (\"") + form->translation + "\" and tx...rz)");
  std::array<double, 3> t{0, 0, 0}, r{0, 0, 0};
  // The value of an entry: {"value": V} or a {"key", "value"} array entry alike.
  auto value_of = [](const RawAttr& a) -> const json& { return a.entry["value"]; };
  if (any_scalar) {
    for (int k = 0; k < 6; ++k) {
      if (!scalar[k]) continue;
      if (!scalar[k]->entry.contains("value")) return malformed(scalar[k]->where, "missing \"value\"");
      double d;
      if (!as_double(value_of(*scalar[k]), d)) return malformed(scalar[k]->where, "expected a number");
      (k < 3 ? t[k] : r[k - 3]) = d;
    }
  } else if (form) {
    std::vector<double> v[2];
    for (int k = 0; k < 2; ++k) {
      if (!vec[k]) continue;
      if (!vec[k]->entry.contains("value")) return malformed(vec[k]->where, "missing \"value\"");
      if (!as_doubles(value_of(*vec[k]), v[k]) || v[k].size() < 3 || v[k].size() % 3 != 0)
        return malformed(vec[k]->where, "expected 3 numbers (or a history pack of 3 per sample)");
    }
    if (!vec[0] || !vec[1])
      warnings.push_back(where + ": the RT link has \"" + (vec[0] ? form->translation : form->rotation) + "\" but no \"" +
                         (vec[0] ? form->rotation : form->translation) + "\": taken as 0");
    const std::size_t samples = (vec[0] ? v[0].size() : v[1].size()) / 3;
    if (vec[0] && vec[1] && v[0].size() != v[1].size())
      return malformed(vec[1]->where, "the history packs of translation and rotation differ in length (" +
                                                     std::to_string(v[0].size()) + " and " +
                                                     std::to_string(v[1].size()) + " numbers)");
    // The newest sample: the greatest of rt_timestamps; without them, rt_head_index; else the
    // first (what CORTEX reads then).
    std::size_t pick = 0;
    bool picked = samples == 1;
    if (!picked && stamps) {
      if (!stamps->entry.contains("value")) return malformed(stamps->where, "missing \"value\"");
      const json& ts = value_of(*stamps);
      std::vector<std::uint64_t> times;
      if (ts.is_array())
        for (const json& e : ts) {
          std::uint64_t x;
          if (!as_uint64(e, x)) return malformed(stamps->where, "expected an array of unsigned integers");
          times.push_back(x);
        }
      if (!ts.is_array() || times.size() != samples)
        return malformed(stamps->where, "expected one time stamp per sample (" + std::to_string(samples) + ")");
      if (std::any_of(times.begin(), times.end(), [&](std::uint64_t x) { return x != times[0]; })) {
        pick = static_cast<std::size_t>(std::max_element(times.begin(), times.end()) - times.begin());
        picked = true;
      }
    }
    if (!picked && head) {
      std::int64_t h;
      bool rounded;
      if (!head->entry.contains("value") || !as_integer(value_of(*head), h, rounded) || rounded || h < 0 || h % 3 != 0 ||
          static_cast<std::uint64_t>(h) / 3 >= samples)
        return malformed(head->where, "expected the index of a sample's first number (0, 3, 6... below " +
                                          std::to_string(3 * samples) + ")");
      pick = static_cast<std::size_t>(h / 3);
      picked = true;
    }
    if (!picked)
      warnings.push_back(where + ": a history pack of " + std::to_string(samples) +
                         " samples without time stamps or head index: the first sample is taken");
    for (int i = 0; i < 3; ++i) {
      if (vec[0]) t[i] = v[0][3 * pick + i];
      if (vec[1]) r[i] = v[1][3 * pick + i];
    }
  } else {
    warnings.push_back(where + ": the RT link has no rt_translation / rt_rotation_euler_xyz: identity");
  }
  if (!form && (stamps || head))
    warnings.push_back(where + ": rt_timestamps / rt_head_index without a history pack: ignored");
  out.pose = internal::pose_from_xyz(t, r, metres_per_unit);
  return out;
}

/// The link attributes the pose is read from (and history-pack bookkeeping), in any layout: an
/// `rt:` attribute of that name cannot be written back onto an RT link.
bool is_pose_key(std::string_view k) {
  for (const char* p : {"rt_translation", "rt_rotation_euler_xyz", "translation", "rotation_euler_xyz", "trans", "rot",
                        "tx", "ty", "tz", "rx", "ry", "rz", "rt_timestamps", "rt_head_index"})
    if (k == p) return true;
  return false;
}

// ------------------------------------------------------------------------------ import

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

// ------------------------------------------------------------------------------ export

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
