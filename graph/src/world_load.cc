// World files loaded: a file read and checked into a plan (nodes, edges, RT edges), then applied
// to a graph in one transaction, or made into a seed delta of its own.

#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "quiver/base/text_position.h"
#include "quiver/graph/limits.h"
#include "quiver/graph/world_file.h"
#include "world_values.h"

namespace quiver::graph {
namespace {

using internal::Failure;
using internal::json;
using internal::parse_value;

struct PlannedNode {
  std::string name, type;
  std::vector<std::pair<Symbol, Value>> attrs;
  std::string where;
};
struct PlannedEdge {
  std::string from, to, type;
  std::vector<std::pair<Symbol, Value>> attrs;
  std::string where;
};
struct PlannedRt {
  std::string parent, child;
  Pose pose;
  std::int64_t stamp = 0;
  std::string where;
};
/// A world file read and checked, not yet applied.
struct Plan {
  std::vector<PlannedNode> nodes;
  std::vector<PlannedEdge> edges;
  std::vector<PlannedRt> rts;
};

bool parse_attrs(const json& j, const std::string& where, std::vector<std::pair<Symbol, Value>>& out, Failure& f) {
  if (j.is_null()) return true;
  if (!j.is_object()) {
    f = Failure{where, "expected an object of attributes"};
    return false;
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (Status s = check_name("the attribute name", it.key()); !s.ok()) {
      f = Failure{where, s.error().message};
      return false;
    }
    Value v;
    if (!parse_value(it.value(), where + "/" + it.key(), v, f)) return false;
    auto name = Symbol::make(it.key());
    if (!name.ok()) {
      f = Failure{where + "/" + it.key(), name.error().message};
      return false;
    }
    out.emplace_back(*name, std::move(v));
  }
  return true;
}

bool parse_string_field(const json& obj, const char* key, const std::string& where, std::string& out, Failure& f,
                        bool required = true) {
  auto it = obj.find(key);
  if (it == obj.end()) {
    if (!required) return true;
    f = Failure{where, std::string("missing \"") + key + "\""};
    return false;
  }
  if (!it->is_string() || it->get<std::string>().empty()) {
    f = Failure{where + "/" + key, "expected a non-empty string"};
    return false;
  }
  out = it->get<std::string>();
  return true;
}

bool parse_doubles(const json& j, std::size_t n, double* out) {
  if (!j.is_array() || j.size() != n) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (!j[i].is_number()) return false;
    out[i] = j[i].get<double>();
    if (!std::isfinite(out[i])) return false;
  }
  return true;
}

bool parse_pose(const json& o, const std::string& where, Pose& p, Failure& f) {
  if (auto t = o.find("translation"); t != o.end() && !parse_doubles(*t, 3, p.translation.data())) {
    f = Failure{where + "/translation", "expected an array of 3 finite numbers"};
    return false;
  }
  auto q = o.find("rotation");
  auto rpy = o.find("rpy");
  if (q != o.end() && rpy != o.end()) {
    f = Failure{where, "give either \"rotation\" (quaternion w,x,y,z) or \"rpy\", not both"};
    return false;
  }
  if (q != o.end()) {
    if (!parse_doubles(*q, 4, p.rotation.data())) {
      f = Failure{where + "/rotation", "expected a quaternion [w, x, y, z] of finite numbers"};
      return false;
    }
    double n = std::sqrt(p.rotation[0] * p.rotation[0] + p.rotation[1] * p.rotation[1] +
                         p.rotation[2] * p.rotation[2] + p.rotation[3] * p.rotation[3]);
    if (n < 1e-9) {
      f = Failure{where + "/rotation", "the quaternion has zero length"};
      return false;
    }
    for (double& x : p.rotation) x /= n;
  } else if (rpy != o.end()) {
    double a[3];
    if (!parse_doubles(*rpy, 3, a)) {
      f = Failure{where + "/rpy", "expected [roll, pitch, yaw] in radians"};
      return false;
    }
    // R = Rz(yaw) * Ry(pitch) * Rx(roll), as in URDF.
    double cr = std::cos(a[0] / 2), sr = std::sin(a[0] / 2), cp = std::cos(a[1] / 2), sp = std::sin(a[1] / 2),
           cy = std::cos(a[2] / 2), sy = std::sin(a[2] / 2);
    p.rotation = {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                  cr * cp * sy - sr * sp * cy};
  }
  if (auto s = o.find("stamp"); s != o.end() && !s->is_number_integer()) {
    f = Failure{where + "/stamp", "expected an integer time stamp"};
    return false;
  }
  return true;
}


// Reads and checks a world file. With a graph `g`, names may refer to nodes it already has and
// options.skip_existing applies; without one (a seed), the file must be complete in itself.
Result<Plan> parse_plan(std::string_view text, const std::string& src, const Graph* g, const WorldLoadOptions& options) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    auto pos = msg.find("; ");  // drop nlohmann's "[json.exception...] parse error at line..." prefix
    std::string why = pos == std::string::npos ? msg : msg.substr(pos + 2);
    return make_error(ErrorCode::kMalformed, src + ":" + line_col(text, e.byte == 0 ? 0 : e.byte - 1) +
                                                 ": JSON syntax error: " + why);
  } catch (const json::exception& e) {
    // E.g. "number overflow parsing '1E999'": locate the quoted token in the text.
    std::string msg = e.what();
    auto close = msg.rfind('\'');
    auto open = close == std::string::npos ? std::string::npos : msg.rfind('\'', close - 1);
    std::size_t at = 0;
    if (open != std::string::npos) {
      auto found = text.find(msg.substr(open + 1, close - open - 1));
      if (found != std::string_view::npos) at = found;
    }
    auto pos = msg.find("] ");
    return make_error(ErrorCode::kMalformed, src + ":" + line_col(text, at) + ": JSON error: " +
                                                 (pos == std::string::npos ? msg : msg.substr(pos + 2)));
  }
  auto fail = [&](const Failure& f) {
    return make_error(ErrorCode::kMalformed, src + ":" + (f.where.empty() ? "/" : f.where) + ": " + f.what);
  };
  if (!root.is_object()) return fail({"", "a world file is a JSON object"});
  auto ver = root.find("quiver_world");
  if (ver == root.end()) return fail({"", "missing \"quiver_world\": 1 (the format version)"});
  if (!ver->is_number_integer() || ver->get<std::int64_t>() != 1)
    return fail({"/quiver_world", "unsupported world format version (this build reads 1)"});
  for (auto it = root.begin(); it != root.end(); ++it)
    if (it.key() != "quiver_world" && it.key() != "nodes" && it.key() != "edges" && it.key() != "rt")
      return fail({"/" + it.key(), "unknown top-level key"});

  Plan plan;
  auto& nodes = plan.nodes;
  auto& edges = plan.edges;
  auto& rts = plan.rts;
  std::unordered_set<std::string> names;
  std::unordered_set<std::string> existing;  // skipped in seed mode
  Failure f;
  if (auto jn = root.find("nodes"); jn != root.end()) {
    if (!jn->is_array()) return fail({"/nodes", "expected an array"});
    for (std::size_t i = 0; i < jn->size(); ++i) {
      const json& o = (*jn)[i];
      std::string where = "/nodes/" + std::to_string(i);
      if (!o.is_object()) return fail({where, "expected an object"});
      PlannedNode n;
      n.where = where;
      if (!parse_string_field(o, "name", where, n.name, f) || !parse_string_field(o, "type", where, n.type, f))
        return fail(f);
      for (auto it = o.begin(); it != o.end(); ++it)
        if (it.key() != "name" && it.key() != "type" && it.key() != "attrs")
          return fail({where + "/" + it.key(), "unknown key"});
      if (n.name.find('~') != std::string::npos) return fail({where + "/name", "'~' is reserved in names"});
      if (!names.insert(n.name).second) return fail({where + "/name", "duplicate node name '" + n.name + "'"});
      if (g && g->find_node(n.name)) {
        if (options.skip_existing) {
          existing.insert(n.name);
          continue;
        }
        return fail({where + "/name", "the graph already has a node named '" + n.name + "'"});
      }
      if (auto a = o.find("attrs"); a != o.end() && !parse_attrs(*a, where + "/attrs", n.attrs, f)) return fail(f);
      nodes.push_back(std::move(n));
    }
  }
  auto known = [&](const std::string& name) { return names.count(name) || (g && g->find_node(name).has_value()); };
  if (auto je = root.find("edges"); je != root.end()) {
    if (!je->is_array()) return fail({"/edges", "expected an array"});
    for (std::size_t i = 0; i < je->size(); ++i) {
      const json& o = (*je)[i];
      std::string where = "/edges/" + std::to_string(i);
      if (!o.is_object()) return fail({where, "expected an object"});
      PlannedEdge e;
      e.where = where;
      if (!parse_string_field(o, "from", where, e.from, f) || !parse_string_field(o, "to", where, e.to, f) ||
          !parse_string_field(o, "type", where, e.type, f))
        return fail(f);
      for (auto it = o.begin(); it != o.end(); ++it)
        if (it.key() != "from" && it.key() != "to" && it.key() != "type" && it.key() != "attrs")
          return fail({where + "/" + it.key(), "unknown key"});
      if (!known(e.from)) return fail({where + "/from", "no node named '" + e.from + "'"});
      if (!known(e.to)) return fail({where + "/to", "no node named '" + e.to + "'"});
      if (e.type == "RT") return fail({where + "/type", "RT edges go in the \"rt\" list"});
      if (auto a = o.find("attrs"); a != o.end() && !parse_attrs(*a, where + "/attrs", e.attrs, f)) return fail(f);
      if (existing.count(e.from) && existing.count(e.to)) continue;
      edges.push_back(std::move(e));
    }
  }
  if (auto jr = root.find("rt"); jr != root.end()) {
    if (!jr->is_array()) return fail({"/rt", "expected an array"});
    std::unordered_map<std::string, std::string> parent_of;
    for (std::size_t i = 0; i < jr->size(); ++i) {
      const json& o = (*jr)[i];
      std::string where = "/rt/" + std::to_string(i);
      if (!o.is_object()) return fail({where, "expected an object"});
      PlannedRt r;
      r.where = where;
      if (!parse_string_field(o, "parent", where, r.parent, f) || !parse_string_field(o, "child", where, r.child, f))
        return fail(f);
      for (auto it = o.begin(); it != o.end(); ++it)
        if (it.key() != "parent" && it.key() != "child" && it.key() != "translation" && it.key() != "rotation" &&
            it.key() != "rpy" && it.key() != "stamp")
          return fail({where + "/" + it.key(), "unknown key"});
      if (!known(r.parent)) return fail({where + "/parent", "no node named '" + r.parent + "'"});
      if (!known(r.child)) return fail({where + "/child", "no node named '" + r.child + "'"});
      if (r.parent == r.child) return fail({where, "a node cannot be its own RT parent"});
      if (!parse_pose(o, where, r.pose, f)) return fail(f);
      if (auto s = o.find("stamp"); s != o.end()) r.stamp = s->get<std::int64_t>();
      if (!parent_of.emplace(r.child, r.parent).second)
        return fail({where + "/child", "'" + r.child + "' already has an RT parent in this file"});
      if (existing.count(r.child)) continue;
      rts.push_back(std::move(r));
    }
  }

  return plan;
}

// Applies a plan in one transaction; errors name the file and the element.
Result<WorldLoadInfo> apply_plan(Graph& g, Plan& plan, const std::string& src) {
  auto tx = g.begin();
  tx.reserve(plan.nodes.size() + plan.edges.size() + plan.rts.size());
  std::unordered_map<std::string, NodeId> ids;
  ids.reserve(plan.nodes.size());
  auto id_of = [&](const std::string& name) -> NodeId {
    auto it = ids.find(name);
    return it != ids.end() ? it->second : *g.find_node(name);
  };
  auto at = [&](const std::string& where, const Error& e) { return make_error(e.code, src + ":" + where + ": " + e.message); };
  for (auto& n : plan.nodes) {
    auto id = tx.create_node(n.type, n.name, std::move(n.attrs));
    if (!id.ok()) return at(n.where, id.error());
    ids.emplace(n.name, *id);
  }
  for (auto& e : plan.edges) {
    Status s = tx.insert_edge(id_of(e.from), id_of(e.to), std::string_view(e.type), std::move(e.attrs));
    if (!s.ok()) return at(e.where, s.error());
  }
  for (const auto& r : plan.rts) {
    Status s = tx.set_rt(id_of(r.parent), id_of(r.child), r.pose, r.stamp);
    if (!s.ok()) return at(r.where, s.error());
  }
  auto committed = tx.commit();
  if (!committed.ok()) return make_error(committed.error().code, src + ": " + committed.error().message);
  return WorldLoadInfo{plan.nodes.size(), plan.edges.size(), plan.rts.size()};
}

}  // namespace

Result<WorldLoadInfo> load_world(Graph& g, std::string_view text, std::string_view source,
                                 const WorldLoadOptions& options) {
  const std::string src(source);
  auto plan = parse_plan(text, src, &g, options);
  if (!plan.ok()) return plan.error();
  return apply_plan(g, *plan, src);
}

Result<WorldSeed> world_seed(std::string_view text, std::string_view source) {
  const std::string src(source);
  auto plan = parse_plan(text, src, nullptr, {});
  if (!plan.ok()) return plan.error();
  // The seed's replica: the file's content hash, incarnation 0 (never an agent's). Built on a
  // scratch replica of that id, so the delta depends on nothing but the file.
  Hasher h(0x5eed);
  h.str(text);
  const ReplicaId origin{h.h64() | 1, 0};
  Graph scratch(origin);
  WorldSeed seed;
  bool got = false;
  scratch.set_delta_sink([&](const GraphDelta& d) {
    seed.delta = d;
    got = true;
  });
  auto info = apply_plan(scratch, *plan, src);
  if (!info.ok()) return info.error();
  if (!got) return make_error(ErrorCode::kInvalidArgument, src + ": the world file is empty");
  seed.delta.seq_lo = seed.delta.seq_hi = 1;
  seed.info = *info;
  return seed;
}

namespace {
Result<std::string> read_text(const char* fn, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kIo, std::string(fn) + ": cannot open '" + path + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

Result<WorldLoadInfo> load_world_file(Graph& g, const std::string& path, const WorldLoadOptions& options) {
  auto text = read_text("load_world_file()", path);
  if (!text.ok()) return text.error();
  return load_world(g, *text, path, options);
}

Result<WorldSeed> world_seed_file(const std::string& path) {
  auto text = read_text("world_seed_file()", path);
  if (!text.ok()) return text.error();
  return world_seed(*text, path);
}

}  // namespace quiver::graph
