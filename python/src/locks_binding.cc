// quiver.LockManager: per-subgraph priority locks on a standalone Graph (docs/locks.md). With no
// peers a claim is held at once. An Agent has its own (Agent.acquire(), ...), which waits for its
// peers' acknowledgement.

#include "common.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/rules/locks/locks.h"

namespace quiver::python {
namespace {

using agents::LockManager;

using PyLocks = OnGraph<LockManager>;

}  // namespace

void bind_locks(py::module_& m) {
  py::class_<PyLocks>(m, "LockManager",
                      "Priority locks on a standalone Graph: acquire(root, priority) claims the scope of `root` "
                      "(the node, its RT descendants and their edges); after install(), writes into a scope "
                      "another replica holds are refused.")
      .def(py::init([](const GraphHandle& h, double lease) {
             if (h.owner.owned()) raise(make_error(ErrorCode::kInvalidArgument, "LockManager(): an agent has its own: Agent.acquire()"));
             PyLocks p;
             p.h = h;
             agents::LockOptions o;
             o.lease_ns = static_cast<std::int64_t>(lease * 1e9);
             p.obj = std::make_unique<LockManager>(*h.graph, nullptr, agents::monotonic_ns, o);
             return p;
           }), py::arg("graph"), py::arg("lease") = 2.0)
      .def("install", [](PyLocks& p) { p.get("install").install(); }, "Installs the lock check as the graph's commit validator.")
      .def("acquire", [](PyLocks& p, py::handle root, std::int64_t priority) {
             check(p.get("acquire").acquire(to_node(p.graph(), root), priority));
           }, py::arg("root"), py::arg("priority"))
      .def("release", [](PyLocks& p, py::handle root) { check(p.get("release").release(to_node(p.graph(), root))); },
           py::arg("root"))
      .def("holds", [](PyLocks& p, py::handle root) { return p.get("holds").holds(to_node(p.graph(), root)); }, py::arg("root"))
      .def("pending", [](PyLocks& p, py::handle root) { return p.get("pending").pending(to_node(p.graph(), root)); }, py::arg("root"))
      .def("winner", [](PyLocks& p, py::handle root) { return p.get("winner").winner(to_node(p.graph(), root)); }, py::arg("root"))
      .def("locked_by_other", [](PyLocks& p, py::handle n) {
             return p.get("locked_by_other").locked_by_other(to_node(p.graph(), n));
           }, py::arg("node"))
      .def("tick", [](PyLocks& p) { p.get("tick").tick(); }, "Renews claims, notices expiry, fires events.");
}

}  // namespace quiver::python
