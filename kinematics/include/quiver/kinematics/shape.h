#pragma once
/// @file
/// Collision shapes as node attributes (schema: docs/kinematics.md).
///
/// A node has a collision shape when its attribute "shape" names one; the shape is fixed in the
/// node's own frame (centred on its origin, axes along the frame's axes):
///
/// | "shape"      | attributes                                                   |
/// | ------------ | ------------------------------------------------------------ |
/// | "box"        | "shape_size": vec3f (or double_vec of 3), full side lengths  |
/// | "sphere"     | "shape_radius": double                                       |
/// | "cylinder"   | "shape_radius", "shape_length" (along z, full length)        |
/// | "capsule"    | "shape_radius", "shape_length" (of the cylindrical part, z)  |
/// | "mesh"       | "shape_mesh": string, an STL (ASCII or binary) or OBJ file; optional
/// "shape_scale": vec3f |
///
/// Lengths are metres. Numbers may be stored as double, float or integers.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::kinematics {

/// Attribute names of the schema.
namespace shape_attr {
inline constexpr const char* kShape = "shape";
inline constexpr const char* kSize = "shape_size";
inline constexpr const char* kRadius = "shape_radius";
inline constexpr const char* kLength = "shape_length";
inline constexpr const char* kMesh = "shape_mesh";
inline constexpr const char* kScale = "shape_scale";
/// True for the attribute names above (a change to one of them rebuilds the shape).
bool is_shape_attr(std::string_view name);
}  // namespace shape_attr

/// A collision shape, fixed in its node's frame.
struct ShapeSpec {
  enum class Kind : std::uint8_t { kBox, kSphere, kCylinder, kCapsule, kMesh };
  Kind kind = Kind::kSphere;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();   ///< box: full side lengths
  double radius = 0.0;                              ///< sphere, cylinder, capsule
  double length = 0.0;                              ///< cylinder, capsule (along z)
  std::string mesh;                                 ///< mesh: file path
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();  ///< mesh: per-axis scale

  friend bool operator==(const ShapeSpec&, const ShapeSpec&) = default;
};

const char* to_string(ShapeSpec::Kind k);

/// Reads a node's shape attributes.
/// @returns nullopt when the node has no "shape" attribute; kInvalidArgument naming the node and
/// the attribute when the attributes do not describe a valid shape (unknown kind, missing or
/// non-positive size, wrong type); kNotFound if the node is not visible.
Result<std::optional<ShapeSpec>> read_shape(const graph::Graph& g, graph::NodeId node);

/// The attributes that describe `s` (for Transaction::create_node or set()).
std::vector<std::pair<graph::Symbol, graph::Value>> shape_attributes(const ShapeSpec& s);

/// A triangle mesh read from a file.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Loads an STL (ASCII or binary) or Wavefront OBJ file (by extension, case-insensitive).
/// @returns kIo when the file cannot be read, kMalformed (with the line or offset) when it does
/// not follow the format, kInvalidArgument for another extension.
Result<TriangleMesh> load_mesh(const std::string& path);

}  // namespace quiver::kinematics
