#pragma once
/// @file
/// URDF import (AGM's `agminner` job): a robot description becomes part of the world graph.
///
///  - every link becomes a node of type "link";
///  - every joint becomes an RT edge parent link -> child link whose transform is the joint's
///    origin (the robot at joint position zero); the child node carries the joint as attributes:
///    "joint" (name), "joint_type" (revolute, continuous, prismatic, fixed, floating, planar),
///    "joint_axis" (vec3f, in the child frame) and, when the URDF gives limits, "joint_lower",
///    "joint_upper", "joint_velocity", "joint_effort" (doubles);
///  - collision geometry becomes shape attributes (quiver/kinematics/shape.h): on the link node
///    itself when the link has one collision element at the link's origin, otherwise on one child
///    node per element, "<link>/collision_<i>" of type "collision", under an RT edge that holds
///    the element's origin. Meshes keep their file name, resolved against the URDF's directory
///    when relative ("package://" URIs are kept as they are, with a warning).
///
/// Malformed input (XML errors, a joint naming a missing link, two roots, a cycle...) is refused
/// with kMalformed and urdfdom's own explanation; nothing is added to the graph then.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::kinematics {

struct UrdfImportOptions {
  /// Attach the root link under this node (created with type "world" if it does not exist).
  /// Empty: the root link is an RT root.
  std::string parent;
  /// X_PR, the pose of the root link in `parent`.
  graph::Pose X_PR;
  /// Prefix of every node name (e.g. "robot1/" to import two copies of a robot).
  std::string prefix;
  /// Directory against which relative mesh paths are resolved (import_urdf_file sets it).
  std::string base_dir;
  /// Stamp of the RT edges (replicated time).
  std::int64_t stamp = 0;
};

struct UrdfImportInfo {
  std::string robot;
  std::size_t links = 0;
  std::size_t joints = 0;
  std::size_t shapes = 0;  ///< collision elements imported as shapes
  std::vector<std::string> warnings;
};

/// Parses `urdf_xml` (named `source` in errors) and adds the robot to `g` in one transaction.
/// @returns kMalformed for invalid URDF, kAlreadyExists if a node name is taken, kInvalidArgument
/// for unsupported geometry.
Result<UrdfImportInfo> import_urdf(graph::Graph& g, std::string_view urdf_xml,
                                   const UrdfImportOptions& options = {},
                                   std::string_view source = "urdf");
/// Reads and imports a URDF file; relative mesh paths resolve against its directory.
/// @returns kIo if the file cannot be read, else as import_urdf().
Result<UrdfImportInfo> import_urdf_file(graph::Graph& g, const std::string& path,
                                        UrdfImportOptions options = {});

}  // namespace quiver::kinematics
