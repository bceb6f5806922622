// RT lookups: quiver.FrameTree (a standalone graph's kinematic tree, owner thread) and
// quiver.FrameReader (lock-free lookups from any one thread; Agent.frames()). Transforms are 4x4
// float64 numpy arrays; X_AB is the pose of frame B in frame A.

#include <Eigen/Geometry>

#include "common.h"
#include "quiver/kinematics/frames.h"

namespace quiver::python {
namespace {

using kinematics::FrameReader;
using kinematics::FrameRef;
using kinematics::FrameTree;

/// A frame named in Python (a node name or a NodeId); owns the text FrameRef points into.
struct Ref {
  std::string name;
  std::optional<graph::NodeId> id;
  FrameRef ref() const { return id ? FrameRef(*id) : FrameRef(std::string_view(name)); }
};
Ref to_ref(py::handle h) {
  Ref r;
  if (PyUnicode_Check(h.ptr())) r.name = h.cast<std::string>();
  else r.id = h.cast<graph::NodeId>();
  return r;
}

py::array_t<double> to_matrix(const Eigen::Isometry3d& X) {
  py::array_t<double> out({4, 4});
  auto o = out.mutable_unchecked<2>();
  const Eigen::Matrix4d M = X.matrix();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) o(i, j) = M(i, j);
  return out;
}

Eigen::Isometry3d to_isometry(py::handle X) {
  graph::Pose p = matrix_to_pose(X, "transform_pose()");
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(p.rotation[0], p.rotation[1], p.rotation[2], p.rotation[3]).toRotationMatrix();
  out.translation() = Eigen::Vector3d(p.translation[0], p.translation[1], p.translation[2]);
  return out;
}

/// The lookups both classes offer, on anything with FrameReader's methods.
template <class Cls, class Get>
void def_lookups(Cls& cls, Get get) {
  cls.def("lookup", [get](typename Cls::type& self, py::handle a, py::handle b) {
        Ref A = to_ref(a), B = to_ref(b);
        return to_matrix(unwrap(get(self).lookup(A.ref(), B.ref())));
      }, py::arg("A"), py::arg("B"), "X_AB now (the pose of frame B in frame A) as a 4x4 array.")
      .def("lookup_at", [get](typename Cls::type& self, py::handle a, py::handle b, std::int64_t t) {
        Ref A = to_ref(a), B = to_ref(b);
        return to_matrix(unwrap(get(self).lookup_at(A.ref(), B.ref(), t)));
      }, py::arg("A"), py::arg("B"), py::arg("t"), "X_AB at replicated time t (interpolated); Error code 'extrapolation' outside the history.")
      .def("transform_point", [get](typename Cls::type& self, py::handle a, py::handle b, std::array<double, 3> p,
                                    std::optional<std::int64_t> t) {
        Ref A = to_ref(a), B = to_ref(b);
        Eigen::Vector3d q = unwrap(get(self).transform_point(A.ref(), B.ref(), Eigen::Vector3d(p[0], p[1], p[2]), t));
        return py::array_t<double>(3, q.data());
      }, py::arg("A"), py::arg("B"), py::arg("p_BoQ_B"), py::arg("t") = py::none(), "A point given in frame B, expressed in frame A.")
      .def("transform_pose", [get](typename Cls::type& self, py::handle a, py::handle b, py::handle X_BC,
                                   std::optional<std::int64_t> t) {
        Ref A = to_ref(a), B = to_ref(b);
        return to_matrix(unwrap(get(self).transform_pose(A.ref(), B.ref(), to_isometry(X_BC), t)));
      }, py::arg("A"), py::arg("B"), py::arg("X_BC"), py::arg("t") = py::none(), "X_AC from X_BC.");
}

using PyFrameTree = OnGraph<FrameTree>;

}  // namespace

void bind_kinematics(py::module_& m) {
  py::class_<FrameReader> reader(m, "FrameReader",
                                 "Lock-free RT lookups for one thread (never waits for the owner of the graph).");
  def_lookups(reader, [](FrameReader& r) -> FrameReader& { return r; });
  reader.def_property_readonly("version", &FrameReader::version, "Bumped whenever the owner publishes a change.");

  py::class_<PyFrameTree> tree(m, "FrameTree",
                               "The kinematic (RT) tree of a standalone Graph, following its changes. For an agent, "
                               "use Agent.frames().");
  tree.def(py::init([](const GraphHandle& h) {
         if (h.owner.owned()) {
           raise(make_error(ErrorCode::kInvalidArgument, "FrameTree(): an agent keeps its own tree: use Agent.frames()"));
         }
         PyFrameTree t;
         t.h = h;
         t.obj = std::make_unique<FrameTree>(*h.graph);
         return t;
       }), py::arg("graph"));
  def_lookups(tree, [](PyFrameTree& t) -> FrameTree& { return t.get("lookup"); });
  tree.def("reader", [](PyFrameTree& t) { return t.get("reader").reader(); }, "A FrameReader for another thread.");
}

}  // namespace quiver::python
