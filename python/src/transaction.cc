// quiver.Transaction: batches local changes into one delta; a context manager that commits on
// success and aborts on an exception.

#include "agent_core.h"
#include "common.h"

namespace quiver::python {
namespace {

using graph::NodeId;
using graph::Symbol;
using graph::Transaction;
using graph::Value;

class PyTransaction {
 public:
  explicit PyTransaction(GraphHandle h) : h_(std::move(h)) { txn_.emplace(h_.get("begin").begin()); }
  ~PyTransaction() {
    // A transaction dropped off its agent's thread is discarded there.
    if (txn_ && h_.owner.agent && !h_.owner.on_owner_thread()) {
      auto moved = std::make_shared<Transaction>(std::move(*txn_));
      auto keep = h_.graph;
      txn_.reset();
      h_.owner.agent->post_quietly([moved, keep]() mutable { moved.reset(); });
    } else if (txn_ && h_.owner.scope && (!h_.owner.scope->open || !h_.owner.on_owner_thread())) {
      // A runtime agent's transaction kept past its run (or dropped on another thread): its graph
      // may be gone, so it is left undestroyed rather than aborted there.
      new Transaction(std::move(*txn_));  // NOLINT: deliberately leaked
      txn_.reset();
    }
  }
  PyTransaction(const PyTransaction&) = delete;
  PyTransaction& operator=(const PyTransaction&) = delete;

  Transaction& txn(const char* fn) {
    h_.owner.check(fn);
    return *txn_;
  }
  graph::Graph& graph() { return *h_.graph; }

 private:
  GraphHandle h_;
  std::optional<Transaction> txn_;
};

std::vector<std::pair<Symbol, Value>> to_attrs(py::handle attrs) {
  std::vector<std::pair<Symbol, Value>> out;
  if (attrs.is_none()) return out;
  for (auto item : py::reinterpret_borrow<py::dict>(attrs)) out.emplace_back(to_symbol(item.first), to_value(item.second));
  return out;
}

Value value_for(const graph::Graph& g, NodeId id, Symbol attr, py::handle value) {
  return to_value(value, g.attr(id, attr));
}

}  // namespace

void bind_transaction(py::module_& m) {
  py::class_<graph::CommitInfo>(m, "CommitInfo", "What a commit published.")
      .def_readonly("ops", &graph::CommitInfo::ops)
      .def_readonly("first_counter", &graph::CommitInfo::first_counter)
      .def_readonly("last_counter", &graph::CommitInfo::last_counter)
      .def("__repr__", [](const graph::CommitInfo& c) { return "<CommitInfo ops=" + std::to_string(c.ops) + ">"; });

  py::class_<PyTransaction>(m, "Transaction",
                            "Local changes batched into one delta. Each call is validated at once (an error raises "
                            "and records nothing); commit() applies them atomically and fires events. Use it as a "
                            "context manager: `with g.transaction() as t: ...` commits at the end, aborts on an "
                            "exception.")
      .def("create_node", [](PyTransaction& p, py::handle type, const std::string& name, py::handle attrs) {
             return unwrap(p.txn("create_node").create_node(to_symbol(type).str(), name, to_attrs(attrs)));
           }, py::arg("type"), py::arg("name"), py::arg("attrs") = py::none(),
           "Creates a node (its id is known at once). Fails if the name is taken or empty.")
      .def("delete_node", [](PyTransaction& p, py::handle n) {
             Transaction& t = p.txn("delete_node");
             check(t.delete_node(to_node(p.graph(), n)));
           }, py::arg("node"))
      .def("set", [](PyTransaction& p, py::handle n, py::handle name, py::handle value) {
             Transaction& t = p.txn("set");
             NodeId id = to_node(p.graph(), n);
             Symbol a = to_symbol(name);
             check(t.set(id, a, value_for(p.graph(), id, a, value)));
           }, py::arg("node"), py::arg("name"), py::arg("value"),
           "Writes an attribute. An existing attribute keeps its type when the value converts to it.")
      .def("update", [](PyTransaction& p, py::handle n, py::dict values) {
             Transaction& t = p.txn("update");
             NodeId id = to_node(p.graph(), n);
             for (auto item : values) {
               Symbol a = to_symbol(item.first);
               check(t.set(id, a, value_for(p.graph(), id, a, item.second)));
             }
           }, py::arg("node"), py::arg("values"), "set() for every name -> value of a dict.")
      .def("remove_attr", [](PyTransaction& p, py::handle n, py::handle name) {
             Transaction& t = p.txn("remove_attr");
             return unwrap(t.remove_attr(to_node(p.graph(), n), to_symbol(name)));
           }, py::arg("node"), py::arg("name"),
           "Removes the attribute; returns True if the node had it (as this transaction sees it), else False.")
      .def("insert_edge", [](PyTransaction& p, py::handle a, py::handle b, py::handle type, py::handle attrs) {
             Transaction& t = p.txn("insert_edge");
             check(t.insert_edge(to_node(p.graph(), a), to_node(p.graph(), b), to_symbol(type), to_attrs(attrs)));
           }, py::arg("source"), py::arg("target"), py::arg("type"), py::arg("attrs") = py::none(),
           "Inserts (or re-inserts) a symbolic edge; a self-loop is a unary predicate. 'RT' is reserved for set_rt().")
      .def("delete_edge", [](PyTransaction& p, py::handle a, py::handle b, py::handle type) {
             Transaction& t = p.txn("delete_edge");
             check(t.delete_edge(to_node(p.graph(), a), to_node(p.graph(), b), to_symbol(type)));
           }, py::arg("source"), py::arg("target"), py::arg("type"))
      .def("set_edge_attr", [](PyTransaction& p, py::handle a, py::handle b, py::handle type, py::handle name,
                               py::handle value) {
             Transaction& t = p.txn("set_edge_attr");
             graph::EdgeKey k{to_node(p.graph(), a), to_node(p.graph(), b), to_symbol(type)};
             Symbol attr = to_symbol(name);
             check(t.set_edge_attr(k, attr, to_value(value, p.graph().edge_attr(k, attr))));
           }, py::arg("source"), py::arg("target"), py::arg("type"), py::arg("name"), py::arg("value"))
      .def("remove_edge_attr", [](PyTransaction& p, py::handle a, py::handle b, py::handle type, py::handle name) {
             Transaction& t = p.txn("remove_edge_attr");
             graph::EdgeKey k{to_node(p.graph(), a), to_node(p.graph(), b), to_symbol(type)};
             return unwrap(t.remove_edge_attr(k, to_symbol(name)));
           }, py::arg("source"), py::arg("target"), py::arg("type"), py::arg("name"))
      .def("set_rt", [](PyTransaction& p, py::handle parent, py::handle child, py::handle X_PC, py::handle translation,
                        py::handle rotation, std::int64_t stamp) {
             Transaction& t = p.txn("set_rt");
             graph::Pose pose;
             if (!X_PC.is_none()) {
               pose = matrix_to_pose(X_PC, "set_rt()");
             } else {
               if (!translation.is_none()) pose.translation = translation.cast<std::array<double, 3>>();
               if (!rotation.is_none()) pose.rotation = rotation.cast<std::array<double, 4>>();
             }
             check(t.set_rt(to_node(p.graph(), parent), to_node(p.graph(), child), pose, stamp));
           }, py::arg("parent"), py::arg("child"), py::arg("X_PC") = py::none(), py::kw_only(),
           py::arg("translation") = py::none(), py::arg("rotation") = py::none(), py::arg("stamp") = 0,
           "Puts `child` under `parent` with X_PC (a 4x4 rigid transform, or translation [x, y, z] and unit "
           "quaternion rotation [w, x, y, z]). Same parent: a pose update; otherwise a move. Refused if it "
           "would close a cycle.")
      .def("remove_rt", [](PyTransaction& p, py::handle child) {
             Transaction& t = p.txn("remove_rt");
             check(t.remove_rt(to_node(p.graph(), child)));
           }, py::arg("child"))
      .def("commit", [](PyTransaction& p) { return unwrap(p.txn("commit").commit()); },
           "Applies the changes as one delta; RefusedError (grammar, locks) or another Error changes nothing.")
      .def("abort", [](PyTransaction& p) { p.txn("abort").abort(); }, "Discards the changes made so far.")
      .def("__len__", [](PyTransaction& p) { return p.txn("__len__").size(); })
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyTransaction& p, py::handle type, py::handle, py::handle) {
             Transaction& t = p.txn("__exit__");
             if (!type.is_none()) {
               t.abort();
               return false;
             }
             if (!t.empty()) unwrap(t.commit());
             return false;
           });

  auto graph_cls = py::reinterpret_borrow<py::class_<GraphHandle>>(m.attr("Graph"));
  graph_cls.def("transaction", [](const GraphHandle& h) { return std::make_unique<PyTransaction>(h); },
                "A new transaction (also a context manager).");
  graph_cls.def("begin", [](const GraphHandle& h) { return std::make_unique<PyTransaction>(h); },
                "A new transaction (same as transaction()).");
}

}  // namespace quiver::python
