// Ids (ReplicaId, NodeId, EdgeKey) and poses (4x4 numpy arrays <-> translation + quaternion).

#include <Eigen/Geometry>
#include <cmath>

#include "common.h"
#include "quiver/base/hash.h"

namespace quiver::python {
namespace {

using graph::EdgeKey;
using graph::NodeId;
using graph::ReplicaId;

}  // namespace

graph::NodeId to_node(const graph::Graph& g, py::handle node) {
  if (PyUnicode_Check(node.ptr())) {
    Py_ssize_t n = 0;
    const char* s = PyUnicode_AsUTF8AndSize(node.ptr(), &n);
    if (s == nullptr) throw py::error_already_set();
    std::string_view name(s, static_cast<std::size_t>(n));
    if (auto id = g.find_node(name)) return *id;
    raise(make_error(ErrorCode::kNotFound, "no node named '" + std::string(name) + "'"));
  }
  return node.cast<NodeId>();
}

py::array_t<double> pose_to_matrix(const graph::Pose& p) {
  Eigen::Quaterniond q(p.rotation[0], p.rotation[1], p.rotation[2], p.rotation[3]);
  Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  py::array_t<double> X({4, 4});
  auto x = X.mutable_unchecked<2>();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) x(i, j) = R(i, j);
    x(i, 3) = p.translation[static_cast<std::size_t>(i)];
    x(3, i) = 0.0;
  }
  x(3, 3) = 1.0;
  return X;
}

graph::Pose matrix_to_pose(py::handle obj, const char* fn) {
  auto X = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!X || X.ndim() != 2 || X.shape(0) != 4 || X.shape(1) != 4) {
    PyErr_Clear();
    raise(make_error(ErrorCode::kInvalidArgument, std::string(fn) + ": a pose is a 4x4 homogeneous transform"));
  }
  auto x = X.unchecked<2>();
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = x(i, j);
  const double err = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(err < 1e-6) || std::abs(R.determinant() - 1.0) > 1e-6 || x(3, 0) != 0 || x(3, 1) != 0 || x(3, 2) != 0 ||
      x(3, 3) != 1) {
    raise(make_error(ErrorCode::kInvalidArgument,
                     std::string(fn) + ": the 4x4 matrix is not a rigid transform (rotation not orthonormal or "
                                       "last row not [0, 0, 0, 1])"));
  }
  Eigen::Quaterniond q(R);
  q.normalize();
  graph::Pose p;
  p.translation = {x(0, 3), x(1, 3), x(2, 3)};
  p.rotation = {q.w(), q.x(), q.y(), q.z()};
  return p;
}

void bind_ids(py::module_& m) {
  py::class_<ReplicaId>(m, "ReplicaId", "One incarnation of one agent.")
      .def(py::init([](std::uint64_t agent, std::uint64_t incarnation) { return ReplicaId{agent, incarnation}; }),
           py::arg("agent"), py::arg("incarnation"))
      .def_readonly("agent", &ReplicaId::agent)
      .def_readonly("incarnation", &ReplicaId::incarnation)
      .def("__eq__", [](const ReplicaId& a, const ReplicaId& b) { return a == b; })
      .def("__hash__", [](const ReplicaId& r) { return static_cast<std::size_t>(hash_value(r)); })
      .def("__str__", &ReplicaId::to_string)
      .def("__repr__", [](const ReplicaId& r) { return "quiver.ReplicaId('" + r.to_string() + "')"; });

  py::class_<NodeId>(m, "NodeId", "A node's id: the dot of its creation. Hashable, ordered.")
      .def_property_readonly("replica", [](const NodeId& n) { return n.dot.replica; })
      .def_property_readonly("counter", [](const NodeId& n) { return n.dot.counter; })
      .def("__eq__", [](const NodeId& a, py::handle b) { return py::isinstance<NodeId>(b) && a == b.cast<NodeId>(); })
      .def("__lt__", [](const NodeId& a, const NodeId& b) { return a < b; })
      .def("__hash__", [](const NodeId& n) { return static_cast<std::size_t>(std::hash<NodeId>{}(n)); })
      .def("__str__", &NodeId::to_string)
      .def("__repr__", [](const NodeId& n) { return "quiver.NodeId('" + n.to_string() + "')"; });

  py::class_<EdgeKey>(m, "EdgeKey", "An edge: its endpoints and its type (RT edges have type 'RT').")
      .def(py::init([](NodeId from, NodeId to, py::handle type) { return EdgeKey{from, to, to_symbol(type)}; }),
           py::arg("source"), py::arg("target"), py::arg("type"))
      .def_readonly("source", &EdgeKey::from)
      .def_readonly("target", &EdgeKey::to)
      .def_property_readonly("type", [](const EdgeKey& k) { return k.type.str(); })
      .def("__eq__", [](const EdgeKey& a, py::handle b) { return py::isinstance<EdgeKey>(b) && a == b.cast<EdgeKey>(); })
      .def("__hash__", [](const EdgeKey& k) { return static_cast<std::size_t>(std::hash<EdgeKey>{}(k)); })
      .def("__str__", &EdgeKey::to_string)
      .def("__repr__", [](const EdgeKey& k) { return "quiver.EdgeKey('" + k.to_string() + "')"; });

  m.def("agent_id", [](const std::string& name) { return fnv1a64(name); }, py::arg("name"),
        "The agent id an agent named `name` has (FNV-1a 64 of the name).");
  m.def("pose_matrix", [](std::array<double, 3> t, std::array<double, 4> q) {
        graph::Pose p;
        p.translation = t;
        p.rotation = q;
        return pose_to_matrix(p);
      },
      py::arg("translation"), py::arg("rotation") = std::array<double, 4>{1, 0, 0, 0},
      "A 4x4 transform from a translation [x, y, z] and a unit quaternion [w, x, y, z].");
}

}  // namespace quiver::python
