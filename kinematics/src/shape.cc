// Collision-shape attributes and mesh files.

#include "quiver/kinematics/shape.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace quiver::kinematics {

using graph::NodeId;
using graph::Value;

bool shape_attr::is_shape_attr(std::string_view name) {
  return name == kShape || name == kSize || name == kRadius || name == kLength || name == kMesh ||
         name == kScale;
}

const char* to_string(ShapeSpec::Kind k) {
  switch (k) {
    case ShapeSpec::Kind::kBox:
      return "box";
    case ShapeSpec::Kind::kSphere:
      return "sphere";
    case ShapeSpec::Kind::kCylinder:
      return "cylinder";
    case ShapeSpec::Kind::kCapsule:
      return "capsule";
    case ShapeSpec::Kind::kMesh:
      return "mesh";
  }
  return "?";
}

namespace {

std::optional<double> as_number(const Value& v) {
  if (auto p = v.get_if<double>()) return *p;
  if (auto p = v.get_if<float>()) return *p;
  if (auto p = v.get_if<std::int64_t>()) return static_cast<double>(*p);
  if (auto p = v.get_if<std::int32_t>()) return static_cast<double>(*p);
  if (auto p = v.get_if<std::uint32_t>()) return static_cast<double>(*p);
  if (auto p = v.get_if<std::uint64_t>()) return static_cast<double>(*p);
  return std::nullopt;
}

std::optional<Eigen::Vector3d> as_vec3(const Value& v) {
  if (auto p = v.get_if<graph::Vec3f>()) return Eigen::Vector3d((*p)[0], (*p)[1], (*p)[2]);
  if (auto p = v.get_if<graph::DoubleVec>(); p && p->size() == 3)
    return Eigen::Vector3d((*p)[0], (*p)[1], (*p)[2]);
  if (auto p = v.get_if<graph::FloatVec>(); p && p->size() == 3)
    return Eigen::Vector3d((*p)[0], (*p)[1], (*p)[2]);
  return std::nullopt;
}

}  // namespace

Result<std::optional<ShapeSpec>> read_shape(const graph::Graph& g, NodeId node) {
  if (!g.has_node(node))
    return make_error(ErrorCode::kNotFound,
                      "read_shape(): node " + node.to_string() + " does not exist");
  const Value* kind = g.attr(node, shape_attr::kShape);
  if (kind == nullptr) return std::optional<ShapeSpec>();
  const std::string who = "read_shape(): node \"" + g.name_of(node) + "\": ";
  const std::string* k = kind->get_if<std::string>();
  if (k == nullptr)
    return make_error(
        ErrorCode::kInvalidArgument,
        who + "attribute 'shape' holds " + graph::to_string(kind->type()) + ", not a string");
  ShapeSpec s;
  auto positive = [&](const char* attr, double* out) -> Status {
    const Value* v = g.attr(node, attr);
    if (v == nullptr)
      return make_error(ErrorCode::kInvalidArgument,
                        who + "a " + *k + " needs the attribute '" + attr + "'");
    auto d = as_number(*v);
    if (!d)
      return make_error(ErrorCode::kInvalidArgument,
                        who + "attribute '" + attr + "' is not a number");
    if (!(*d > 0.0) || !std::isfinite(*d))
      return make_error(
          ErrorCode::kInvalidArgument,
          who + "attribute '" + attr + "' must be a positive length, not " + v->to_string());
    *out = *d;
    return Status::Ok();
  };
  if (*k == "box") {
    s.kind = ShapeSpec::Kind::kBox;
    const Value* v = g.attr(node, shape_attr::kSize);
    if (v == nullptr)
      return make_error(ErrorCode::kInvalidArgument,
                        who + "a box needs the attribute 'shape_size' (vec3f)");
    auto size = as_vec3(*v);
    if (!size)
      return make_error(ErrorCode::kInvalidArgument, who + "attribute 'shape_size' is not a vec3f");
    if (!(size->minCoeff() > 0.0) || !size->allFinite())
      return make_error(ErrorCode::kInvalidArgument,
                        who + "attribute 'shape_size' must be positive, not " + v->to_string());
    s.size = *size;
  } else if (*k == "sphere") {
    s.kind = ShapeSpec::Kind::kSphere;
    if (Status st = positive(shape_attr::kRadius, &s.radius); !st.ok()) return st.error();
  } else if (*k == "cylinder" || *k == "capsule") {
    s.kind = *k == "cylinder" ? ShapeSpec::Kind::kCylinder : ShapeSpec::Kind::kCapsule;
    if (Status st = positive(shape_attr::kRadius, &s.radius); !st.ok()) return st.error();
    if (Status st = positive(shape_attr::kLength, &s.length); !st.ok()) return st.error();
  } else if (*k == "mesh") {
    s.kind = ShapeSpec::Kind::kMesh;
    const Value* v = g.attr(node, shape_attr::kMesh);
    const std::string* path = v ? v->get_if<std::string>() : nullptr;
    if (path == nullptr || path->empty())
      return make_error(ErrorCode::kInvalidArgument,
                        who + "a mesh needs the attribute 'shape_mesh' (a file path)");
    s.mesh = *path;
    if (const Value* sc = g.attr(node, shape_attr::kScale)) {
      auto scale = as_vec3(*sc);
      if (!scale || !(scale->cwiseAbs().minCoeff() > 0.0) || !scale->allFinite())
        return make_error(ErrorCode::kInvalidArgument,
                          who + "attribute 'shape_scale' must be a vec3f of non-zero numbers");
      s.scale = *scale;
    }
  } else {
    return make_error(
        ErrorCode::kInvalidArgument,
        who + "unknown shape '" + *k + "' (expected box, sphere, cylinder, capsule or mesh)");
  }
  return std::optional<ShapeSpec>(s);
}

std::vector<std::pair<graph::Symbol, Value>> shape_attributes(const ShapeSpec& s) {
  using graph::Symbol;
  std::vector<std::pair<Symbol, Value>> out;
  out.emplace_back(Symbol(shape_attr::kShape), Value(to_string(s.kind)));
  auto vec = [](const Eigen::Vector3d& v) {
    return Value(graph::Vec3f{static_cast<float>(v.x()), static_cast<float>(v.y()),
                              static_cast<float>(v.z())});
  };
  switch (s.kind) {
    case ShapeSpec::Kind::kBox:
      out.emplace_back(Symbol(shape_attr::kSize), vec(s.size));
      break;
    case ShapeSpec::Kind::kSphere:
      out.emplace_back(Symbol(shape_attr::kRadius), Value(s.radius));
      break;
    case ShapeSpec::Kind::kCylinder:
    case ShapeSpec::Kind::kCapsule:
      out.emplace_back(Symbol(shape_attr::kRadius), Value(s.radius));
      out.emplace_back(Symbol(shape_attr::kLength), Value(s.length));
      break;
    case ShapeSpec::Kind::kMesh:
      out.emplace_back(Symbol(shape_attr::kMesh), Value(s.mesh));
      if (s.scale != Eigen::Vector3d::Ones())
        out.emplace_back(Symbol(shape_attr::kScale), vec(s.scale));
      break;
  }
  return out;
}

// ------------------------------------------------------------------------------------ meshes

namespace {

std::string lower_ext(const std::string& path) {
  auto dot = path.rfind('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

Error malformed(const std::string& path, const std::string& where, const std::string& what) {
  return make_error(ErrorCode::kMalformed, "load_mesh(): " + path + ":" + where + ": " + what);
}

Result<TriangleMesh> parse_stl(const std::string& path, const std::string& data) {
  TriangleMesh m;
  auto read_f32 = [&](std::size_t at) {
    float f;
    std::memcpy(&f, data.data() + at, 4);
    return static_cast<double>(f);
  };
  // Binary: 80-byte header, uint32 count, 50 bytes per triangle. Some binary files start with
  // "solid" too, so the size decides.
  if (data.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    if (84 + 50ull * n == data.size()) {
      m.vertices.reserve(3ull * n);
      for (std::uint32_t t = 0; t < n; ++t) {
        const std::size_t base = 84 + 50ull * t + 12;  // skip the normal
        for (int v = 0; v < 3; ++v)
          m.vertices.emplace_back(read_f32(base + 12 * v), read_f32(base + 12 * v + 4),
                                  read_f32(base + 12 * v + 8));
        m.triangles.push_back({int(3 * t), int(3 * t + 1), int(3 * t + 2)});
      }
      if (m.triangles.empty()) return malformed(path, "0", "no triangles");
      return m;
    }
  }
  // ASCII.
  std::istringstream in(data);
  std::string word;
  in >> word;
  if (word != "solid")
    return malformed(path, "1", "neither a binary STL (size mismatch) nor an ASCII one ('solid')");
  std::string line;
  int lineno = 1;
  int in_facet = 0;
  std::getline(in, line);
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string w;
    if (!(ls >> w)) continue;
    if (w == "vertex") {
      double x, y, z;
      if (!(ls >> x >> y >> z))
        return malformed(path, std::to_string(lineno), "expected three numbers after 'vertex'");
      m.vertices.emplace_back(x, y, z);
      ++in_facet;
    } else if (w == "endfacet") {
      if (in_facet != 3)
        return malformed(path, std::to_string(lineno), "a facet must have exactly 3 vertices");
      const int b = static_cast<int>(m.vertices.size()) - 3;
      m.triangles.push_back({b, b + 1, b + 2});
      in_facet = 0;
    }
  }
  if (m.triangles.empty()) return malformed(path, std::to_string(lineno), "no triangles");
  return m;
}

Result<TriangleMesh> parse_obj(const std::string& path, const std::string& data) {
  TriangleMesh m;
  std::istringstream in(data);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string w;
    if (!(ls >> w) || w[0] == '#') continue;
    if (w == "v") {
      double x, y, z;
      if (!(ls >> x >> y >> z))
        return malformed(path, std::to_string(lineno), "expected three numbers after 'v'");
      m.vertices.emplace_back(x, y, z);
    } else if (w == "f") {
      std::vector<int> idx;
      std::string tok;
      while (ls >> tok) {
        // "i", "i/t", "i//n", "i/t/n"; negative indices count from the end.
        int i = 0;
        try {
          i = std::stoi(tok.substr(0, tok.find('/')));
        } catch (...) {
          return malformed(path, std::to_string(lineno), "bad face index '" + tok + "'");
        }
        if (i < 0) i = static_cast<int>(m.vertices.size()) + i + 1;
        if (i < 1 || i > static_cast<int>(m.vertices.size()))
          return malformed(path, std::to_string(lineno), "face index " + tok + " is out of range");
        idx.push_back(i - 1);
      }
      if (idx.size() < 3)
        return malformed(path, std::to_string(lineno), "a face needs at least 3 vertices");
      for (std::size_t k = 1; k + 1 < idx.size(); ++k)
        m.triangles.push_back({idx[0], idx[k], idx[k + 1]});
    }
  }
  if (m.triangles.empty()) return malformed(path, std::to_string(lineno), "no faces");
  return m;
}

}  // namespace

Result<TriangleMesh> load_mesh(const std::string& path) {
  const std::string ext = lower_ext(path);
  if (ext != "stl" && ext != "obj")
    return make_error(
        ErrorCode::kInvalidArgument,
        "load_mesh(): " + path + ": unsupported mesh format '" + ext + "' (STL and OBJ are read)");
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return make_error(ErrorCode::kIo,
                      "load_mesh(): cannot open " + path + ": " + std::strerror(errno));
  std::ostringstream ss;
  ss << f.rdbuf();
  const std::string data = ss.str();
  return ext == "stl" ? parse_stl(path, data) : parse_obj(path, data);
}

}  // namespace quiver::kinematics
