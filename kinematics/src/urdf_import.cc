// URDF -> world graph, through urdfdom.

#include "quiver/kinematics/urdf_import.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "quiver/kinematics/shape.h"

namespace quiver::kinematics {

using graph::NodeId;
using graph::Pose;
using graph::Symbol;
using graph::Value;

namespace {

/// Collects urdfdom's log lines while it parses (console_bridge's handler is process-wide, so
/// parses are serialised).
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR)
      errors.push_back(text);
    else if (level == console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      warnings.push_back(text);
  }
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
};

std::mutex& parse_mutex() {
  static std::mutex m;
  return m;
}

Pose to_pose(const urdf::Pose& p) {
  Pose out;
  out.translation = {p.position.x, p.position.y, p.position.z};
  double w = p.rotation.w, x = p.rotation.x, y = p.rotation.y, z = p.rotation.z;
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  if (n > 0) out.rotation = {w / n, x / n, y / n, z / n};
  return out;
}

bool is_identity(const urdf::Pose& p) {
  return p.position.x == 0 && p.position.y == 0 && p.position.z == 0 && p.rotation.x == 0 &&
         p.rotation.y == 0 && p.rotation.z == 0;
}

const char* joint_type(int t) {
  switch (t) {
    case urdf::Joint::REVOLUTE:
      return "revolute";
    case urdf::Joint::CONTINUOUS:
      return "continuous";
    case urdf::Joint::PRISMATIC:
      return "prismatic";
    case urdf::Joint::FLOATING:
      return "floating";
    case urdf::Joint::PLANAR:
      return "planar";
    case urdf::Joint::FIXED:
      return "fixed";
    default:
      return "unknown";
  }
}

std::string resolve_mesh(const std::string& file, const std::string& base_dir,
                         std::vector<std::string>& warnings) {
  if (file.rfind("package://", 0) == 0) {
    warnings.push_back("mesh '" + file + "': package:// URIs are not resolved; kept as is");
    return file;
  }
  std::string path = file.rfind("file://", 0) == 0 ? file.substr(7) : file;
  if (!path.empty() && path[0] != '/' && !base_dir.empty()) path = base_dir + "/" + path;
  return path;
}

/// The shape of one URDF collision geometry.
Result<ShapeSpec> to_shape(const urdf::Geometry& geom, const std::string& where,
                           const std::string& base_dir, std::vector<std::string>& warnings) {
  ShapeSpec s;
  switch (geom.type) {
    case urdf::Geometry::SPHERE:
      s.kind = ShapeSpec::Kind::kSphere;
      s.radius = static_cast<const urdf::Sphere&>(geom).radius;
      break;
    case urdf::Geometry::BOX: {
      s.kind = ShapeSpec::Kind::kBox;
      const auto& d = static_cast<const urdf::Box&>(geom).dim;
      s.size = Eigen::Vector3d(d.x, d.y, d.z);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      s.kind = ShapeSpec::Kind::kCylinder;
      const auto& c = static_cast<const urdf::Cylinder&>(geom);
      s.radius = c.radius;
      s.length = c.length;
      break;
    }
    case urdf::Geometry::MESH: {
      s.kind = ShapeSpec::Kind::kMesh;
      const auto& m = static_cast<const urdf::Mesh&>(geom);
      if (m.filename.empty())
        return make_error(ErrorCode::kMalformed, where + ": a mesh geometry needs a filename");
      s.mesh = resolve_mesh(m.filename, base_dir, warnings);
      s.scale = Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z);
      break;
    }
    default:
      return make_error(ErrorCode::kInvalidArgument, where + ": unsupported geometry type");
  }
  const bool positive = s.kind == ShapeSpec::Kind::kBox      ? s.size.minCoeff() > 0
                        : s.kind == ShapeSpec::Kind::kSphere ? s.radius > 0
                        : s.kind == ShapeSpec::Kind::kMesh   ? true
                                                             : s.radius > 0 && s.length > 0;
  if (!positive)
    return make_error(ErrorCode::kMalformed,
                      where + ": the " + to_string(s.kind) + " has a zero or negative size");
  return s;
}

}  // namespace

Result<UrdfImportInfo> import_urdf(graph::Graph& g, std::string_view urdf_xml,
                                   const UrdfImportOptions& options, std::string_view source) {
  const std::string src(source);
  urdf::ModelInterfaceSharedPtr model;
  CaptureHandler capture;
  {
    std::lock_guard lock(parse_mutex());
    console_bridge::useOutputHandler(&capture);
    try {
      model = urdf::parseURDF(std::string(urdf_xml));
    } catch (const std::exception& e) {  // urdfdom throws on some malformed numbers
      capture.errors.push_back(e.what());
      model.reset();
    }
    console_bridge::restorePreviousOutputHandler();
  }
  // urdfdom skips some invalid elements (a collision with a bad radius...) with an error message
  // and still returns a model: any error refuses the file.
  if (!model || !capture.errors.empty()) {
    std::string why;
    for (const std::string& l : capture.errors) why += (why.empty() ? "" : "; ") + l;
    if (why.empty()) why = "not a valid URDF document";
    return make_error(ErrorCode::kMalformed, "import_urdf(): " + src + ": " + why);
  }
  UrdfImportInfo info;
  info.warnings = capture.warnings;
  info.robot = model->getName();
  if (!model->getRoot())
    return make_error(ErrorCode::kMalformed,
                      "import_urdf(): " + src + ": the robot has no root link");

  auto tx = g.begin();
  std::unordered_map<std::string, NodeId> link_node;
  auto create = [&](const std::string& type, const std::string& name,
                    std::vector<std::pair<Symbol, Value>> attrs) -> Result<NodeId> {
    auto id = tx.create_node(type, options.prefix + name, std::move(attrs));
    if (!id.ok()) {
      Error e = id.error();
      e.message = "import_urdf(): " + src + ": " + e.message;
      if (g.find_node(options.prefix + name)) e.code = ErrorCode::kAlreadyExists;
      return e;
    }
    return id;
  };

  // Links, with their collision geometry.
  for (const auto& [name, link] : model->links_) {
    std::vector<std::pair<Symbol, Value>> attrs;
    const auto& collisions = link->collision_array;
    const bool inline_shape =
        collisions.size() == 1 && collisions[0]->geometry && is_identity(collisions[0]->origin);
    if (inline_shape) {
      auto shape = to_shape(*collisions[0]->geometry, src + ": link '" + name + "'",
                            options.base_dir, info.warnings);
      if (!shape.ok()) return Error{shape.error().code, "import_urdf(): " + shape.error().message};
      attrs = shape_attributes(*shape);
      ++info.shapes;
    }
    auto id = create("link", name, std::move(attrs));
    if (!id.ok()) return id.error();
    link_node[name] = *id;
    ++info.links;
    if (inline_shape) continue;
    for (std::size_t i = 0; i < collisions.size(); ++i) {
      if (!collisions[i]->geometry) continue;
      const std::string where = src + ": link '" + name + "' collision " + std::to_string(i);
      auto shape = to_shape(*collisions[i]->geometry, where, options.base_dir, info.warnings);
      if (!shape.ok()) return Error{shape.error().code, "import_urdf(): " + shape.error().message};
      auto cid =
          create("collision", name + "/collision_" + std::to_string(i), shape_attributes(*shape));
      if (!cid.ok()) return cid.error();
      if (Status s = tx.set_rt(*id, *cid, to_pose(collisions[i]->origin), options.stamp); !s.ok())
        return Error{s.error().code, "import_urdf(): " + src + ": " + s.error().message};
      ++info.shapes;
    }
  }

  // Joints: RT edges with their origins; the joint itself as attributes of the child link.
  for (const auto& [name, joint] : model->joints_) {
    auto p = link_node.find(joint->parent_link_name);
    auto c = link_node.find(joint->child_link_name);
    if (p == link_node.end() || c == link_node.end())
      return make_error(ErrorCode::kMalformed,
                        "import_urdf(): " + src + ": joint '" + name + "' links missing links '" +
                            joint->parent_link_name + "' -> '" + joint->child_link_name + "'");
    if (Status s = tx.set_rt(p->second, c->second, to_pose(joint->parent_to_joint_origin_transform),
                             options.stamp);
        !s.ok())
      return Error{s.error().code,
                   "import_urdf(): " + src + ": joint '" + name + "': " + s.error().message};
    (void)tx.set(c->second, "joint", Value(name));
    (void)tx.set(c->second, "joint_type", Value(joint_type(joint->type)));
    if (joint->type != urdf::Joint::FIXED && joint->type != urdf::Joint::FLOATING)
      (void)tx.set(
          c->second, "joint_axis",
          Value(graph::Vec3f{static_cast<float>(joint->axis.x), static_cast<float>(joint->axis.y),
                             static_cast<float>(joint->axis.z)}));
    if (joint->limits) {
      (void)tx.set(c->second, "joint_lower", Value(joint->limits->lower));
      (void)tx.set(c->second, "joint_upper", Value(joint->limits->upper));
      (void)tx.set(c->second, "joint_velocity", Value(joint->limits->velocity));
      (void)tx.set(c->second, "joint_effort", Value(joint->limits->effort));
    }
    ++info.joints;
  }

  // Attach the root link.
  if (!options.parent.empty()) {
    NodeId parent;
    if (auto existing = g.find_node(options.parent)) {
      parent = *existing;
    } else {
      auto id = tx.create_node("world", options.parent);
      if (!id.ok()) return Error{id.error().code, "import_urdf(): " + id.error().message};
      parent = *id;
    }
    const NodeId root = link_node.at(model->getRoot()->name);
    if (Status s = tx.set_rt(parent, root, options.X_PR, options.stamp); !s.ok())
      return Error{s.error().code, "import_urdf(): " + src + ": " + s.error().message};
  }
  auto committed = tx.commit();
  if (!committed.ok())
    return Error{committed.error().code, "import_urdf(): " + committed.error().message};
  return info;
}

Result<UrdfImportInfo> import_urdf_file(graph::Graph& g, const std::string& path,
                                        UrdfImportOptions options) {
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return make_error(ErrorCode::kIo,
                      "import_urdf(): cannot open " + path + ": " + std::strerror(errno));
  std::ostringstream ss;
  ss << f.rdbuf();
  if (options.base_dir.empty()) {
    auto slash = path.rfind('/');
    options.base_dir = slash == std::string::npos ? "." : path.substr(0, slash);
  }
  return import_urdf(g, ss.str(), options, path);
}

}  // namespace quiver::kinematics
