// quiver.Graph: reads of a replica, its change events, state exchange. Writes go through
// transactions (transaction.cc).

#include "common.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/base/hash.h"
#include "quiver/graph/world_file.h"
#include "quiver/interop/any_world.h"
#include "quiver/interop/interop.h"

namespace quiver::python {
namespace {

using graph::ChangeBatch;
using graph::EdgeChange;
using graph::EdgeKey;
using graph::Graph;
using graph::NodeChange;
using graph::NodeId;
using graph::Symbol;

py::dict values_dict(const std::vector<std::pair<Symbol, graph::Value>>& values) {
  py::dict d;
  for (const auto& [name, v] : values) d[py::str(name.str())] = from_value(v);
  return d;
}

std::vector<std::string> names(const std::vector<Symbol>& syms) {
  std::vector<std::string> out;
  out.reserve(syms.size());
  for (Symbol s : syms) out.push_back(s.str());
  return out;
}

Symbol optional_symbol(py::handle type) { return type.is_none() ? Symbol() : to_symbol(type); }

/// An edge given as an EdgeKey or a (source, target, type) tuple (nodes by id or name).
EdgeKey to_edge(const Graph& g, py::handle e) {
  if (py::isinstance<EdgeKey>(e)) return e.cast<EdgeKey>();
  auto t = py::reinterpret_borrow<py::sequence>(e);
  if (!py::isinstance<py::sequence>(e) || py::len(t) != 3) {
    raise(make_error(ErrorCode::kInvalidArgument, "an edge is an EdgeKey or a (source, target, type) tuple"));
  }
  return EdgeKey{to_node(g, t[0]), to_node(g, t[1]), to_symbol(t[2])};
}

/// Reads an attribute as a named type with Graph::get<T>, so the error is the C++ one.
template <std::size_t I = 0>
py::object get_as(const Graph& g, NodeId id, std::string_view name, graph::ValueType t) {
  if constexpr (I == graph::kValueTypeCount) {
    return py::none();
  } else {
    using Types = std::tuple<std::string, bool, std::int32_t, std::int64_t, std::uint32_t, std::uint64_t, float,
                             double, graph::Bytes, graph::FloatVec, graph::DoubleVec, graph::UInt64Vec,
                             graph::Vec2f, graph::Vec3f, graph::Vec4f, graph::Vec6f, graph::Mat4d>;
    if (static_cast<std::size_t>(t) == I + 1) {
      auto r = g.get<std::tuple_element_t<I, Types>>(id, name);
      return from_value(graph::Value(unwrap(std::move(r))));
    }
    return get_as<I + 1>(g, id, name, t);
  }
}

py::dict attrs_of(const std::vector<Symbol>& attr_names, auto&& read) {
  py::dict d;
  for (Symbol a : attr_names)
    if (const graph::Value* v = read(a)) d[py::str(a.str())] = from_value(*v);
  return d;
}

/// Opaque state of a replica, for Graph.merge().
struct GraphState {
  graph::GraphDelta delta;
};

}  // namespace

void bind_graph(py::module_& m) {
  m.def(
      "convert_world",
      [](const std::string& path) {
        std::string text = unwrap(interop::read_file("convert_world()", path));
        if (interop::detect_format(text) == interop::WorldFormat::kQuiverJson) return text;
        graph::Graph g(graph::ReplicaId{fnv1a64("convert_world"), 1});
        if (Status s = interop::load_any_world(g, text, path); !s.ok())
          raise(make_error(s.error().code, "convert_world(): " + s.error().message));
        return graph::save_world(g);
      },
      py::arg("path"),
      "A world file of any kind the importers read (Quiver JSON, CORTEX DSR JSON, AGM XML; docs/interop.md) as "
      "Quiver world JSON text, e.g. for Agent(world_text=...).");
  py::class_<NodeChange>(m, "NodeChange")
      .def_readonly("id", &NodeChange::id)
      .def_property_readonly("kind", [](const NodeChange& c) { return std::string(to_string(c.kind)); })
      .def_property_readonly("type", [](const NodeChange& c) { return c.type.str(); })
      .def_property_readonly("attrs", [](const NodeChange& c) { return names(c.attrs); })
      .def_readonly("renamed", &NodeChange::renamed)
      .def_readonly("name", &NodeChange::name, "deleted: the node's last name (else empty)")
      .def_property_readonly(
          "values", [](const NodeChange& c) { return values_dict(c.values); },
          "deleted: the node's last attribute values, a dict (else empty)")
      .def("__repr__", [](const NodeChange& c) {
        return std::string("<NodeChange ") + to_string(c.kind) + " " + c.type.str() + " " + c.id.to_string() + ">";
      });
  py::class_<EdgeChange>(m, "EdgeChange")
      .def_readonly("key", &EdgeChange::key)
      .def_property_readonly("kind", [](const EdgeChange& c) { return std::string(to_string(c.kind)); })
      .def_property_readonly("attrs", [](const EdgeChange& c) { return names(c.attrs); })
      .def_property_readonly(
          "values", [](const EdgeChange& c) { return values_dict(c.values); },
          "deleted: the edge's last attribute values, a dict (else empty)")
      .def("__repr__", [](const EdgeChange& c) {
        return std::string("<EdgeChange ") + to_string(c.kind) + " " + c.key.to_string() + ">";
      });
  py::class_<ChangeBatch>(m, "ChangeBatch", "Everything one commit or one merge changed.")
      .def_readonly("local", &ChangeBatch::local)
      .def_readonly("origin", &ChangeBatch::origin)
      .def_readonly("origin_name", &ChangeBatch::origin_name,
                    "The name of the agent whose change this is (its id as text when unknown).")
      .def_readonly("nodes", &ChangeBatch::nodes)
      .def_readonly("edges", &ChangeBatch::edges)
      .def("__repr__", [](const ChangeBatch& b) {
        return "<ChangeBatch " + std::string(b.local ? "local" : "remote") + " nodes=" + std::to_string(b.nodes.size()) +
               " edges=" + std::to_string(b.edges.size()) + ">";
      });
  py::class_<GraphState>(m, "GraphState", "The whole state of a replica (Graph.state()), to merge into another.");

  py::class_<GraphHandle>(m, "Graph",
                          "A replica of the world graph. A standalone Graph may be used from any Python thread; "
                          "an agent's graph only on the agent's thread (inside Agent.call() or a callback).")
      .def(py::init([](const std::string& name, std::uint64_t incarnation) {
             GraphHandle h;
             h.graph = std::make_shared<Graph>(graph::ReplicaId{fnv1a64(name), incarnation});
             return h;
           }),
           py::arg("name") = "local", py::arg("incarnation") = 1,
           "A standalone replica whose agent id derives from `name`.")
      .def_property_readonly("replica", [](const GraphHandle& h) { return h.get("replica").replica(); })
      .def("has_node", [](const GraphHandle& h, py::handle n) {
             Graph& g = h.get("has_node");
             if (PyUnicode_Check(n.ptr())) return g.find_node(n.cast<std::string>()).has_value();
             return g.has_node(n.cast<NodeId>());
           }, py::arg("node"))
      .def_property_readonly("node_count", [](const GraphHandle& h) { return h.get("node_count").node_count(); })
      .def_property_readonly("edge_count", [](const GraphHandle& h) { return h.get("edge_count").edge_count(); })
      .def("nodes", [](const GraphHandle& h, py::handle type) {
             Graph& g = h.get("nodes");
             return type.is_none() ? g.nodes() : g.nodes_of_type(to_symbol(type));
           }, py::arg("type") = py::none(), "Visible nodes (of one type if given).")
      .def("find_node", [](const GraphHandle& h, const std::string& name) { return h.get("find_node").find_node(name); },
           py::arg("name"), "The node with this name, or None.")
      .def("node", [](const GraphHandle& h, py::handle n) { return to_node(h.get("node"), n); }, py::arg("name"),
           "The node with this name (NotFoundError if none).")
      .def("type_of", [](const GraphHandle& h, py::handle n) {
             Graph& g = h.get("type_of");
             return g.type_of(to_node(g, n)).str();
           }, py::arg("node"))
      .def("name_of", [](const GraphHandle& h, py::handle n) {
             Graph& g = h.get("name_of");
             return g.name_of(to_node(g, n));
           }, py::arg("node"))
      .def("find_name", [](const GraphHandle& h, const NodeId& id) { return h.get("find_name").find_name(id); },
           py::arg("node"), "The name of a visible node, or None (where name_of() gives '').")
      .def("namesakes", [](const GraphHandle& h, const std::string& name) { return h.get("namesakes").namesakes(name); },
           py::arg("name"))
      .def("get", [](const GraphHandle& h, py::handle n, py::handle name, py::object default_value, py::handle type) {
             Graph& g = h.get("get");
             NodeId id = to_node(g, n);
             if (!type.is_none()) {
               auto t = graph::value_type_from_string(type.cast<std::string>());
               if (!t) raise(make_error(ErrorCode::kInvalidArgument, "get(): unknown type '" + type.cast<std::string>() + "'"));
               return get_as(g, id, to_symbol(name).str(), *t);
             }
             const graph::Value* v = g.attr(id, to_symbol(name));
             if (v != nullptr) return from_value(*v);
             if (!default_value.is(py::ellipsis())) return default_value;
             raise(make_error(ErrorCode::kNotFound, "get(): node '" + g.name_of(id) + "' has no attribute '" +
                                                        to_symbol(name).str() + "'"));
           },
           py::arg("node"), py::arg("name"), py::arg("default") = py::ellipsis(), py::arg("type") = py::none(),
           "The winning value of an attribute. Missing: `default` if given, else NotFoundError. With `type` "
           "('double', 'vec3f', ...), a value of another type raises TypeMismatchError.")
      .def("value", [](const GraphHandle& h, py::handle n, py::handle name) -> std::optional<graph::Value> {
             Graph& g = h.get("value");
             const graph::Value* v = g.attr(to_node(g, n), to_symbol(name));
             if (v == nullptr) return std::nullopt;
             return *v;
           }, py::arg("node"), py::arg("name"), "The attribute as a typed quiver.Value, or None.")
      .def("values", [](const GraphHandle& h, py::handle n, py::handle name) {
             Graph& g = h.get("values");
             py::list out;
             for (const graph::AttrValue& v : g.attr_values(to_node(g, n), to_symbol(name))) out.append(from_value(v.value));
             return out;
           }, py::arg("node"), py::arg("name"), "Every concurrent value of an attribute, winner first.")
      .def("attrs", [](const GraphHandle& h, py::handle n) {
             Graph& g = h.get("attrs");
             NodeId id = to_node(g, n);
             return attrs_of(g.attr_names(id), [&](Symbol a) { return g.attr(id, a); });
           }, py::arg("node"), "Every attribute of a node as a dict.")
      .def("has_edge", [](const GraphHandle& h, py::handle a, py::handle b, py::handle type) {
             Graph& g = h.get("has_edge");
             return g.has_edge(to_node(g, a), to_node(g, b), to_symbol(type));
           }, py::arg("source"), py::arg("target"), py::arg("type"))
      .def("edges_from", [](const GraphHandle& h, py::handle n, py::handle type) {
             Graph& g = h.get("edges_from");
             return g.edges_from(to_node(g, n), optional_symbol(type));
           }, py::arg("node"), py::arg("type") = py::none())
      .def("edges_to", [](const GraphHandle& h, py::handle n, py::handle type) {
             Graph& g = h.get("edges_to");
             return g.edges_to(to_node(g, n), optional_symbol(type));
           }, py::arg("node"), py::arg("type") = py::none())
      .def("edges", [](const GraphHandle& h, py::handle type) { return h.get("edges").edges_of_type(to_symbol(type)); },
           py::arg("type"))
      .def("edge_get", [](const GraphHandle& h, py::handle e, py::handle name, py::object default_value) {
             Graph& g = h.get("edge_get");
             EdgeKey k = to_edge(g, e);
             if (const graph::Value* v = g.edge_attr(k, to_symbol(name))) return from_value(*v);
             if (!default_value.is(py::ellipsis())) return default_value;
             raise(make_error(ErrorCode::kNotFound, "edge_get(): edge " + k.to_string() + " has no attribute '" +
                                                        to_symbol(name).str() + "'"));
           }, py::arg("edge"), py::arg("name"), py::arg("default") = py::ellipsis())
      .def("edge_attrs", [](const GraphHandle& h, py::handle e) {
             Graph& g = h.get("edge_attrs");
             EdgeKey k = to_edge(g, e);
             return attrs_of(g.edge_attr_names(k), [&](Symbol a) { return g.edge_attr(k, a); });
           }, py::arg("edge"))
      .def("rt_parent", [](const GraphHandle& h, py::handle n) {
             Graph& g = h.get("rt_parent");
             return g.rt_parent(to_node(g, n));
           }, py::arg("child"))
      .def("rt_children", [](const GraphHandle& h, py::handle n) {
             Graph& g = h.get("rt_children");
             return g.rt_children(to_node(g, n));
           }, py::arg("parent"))
      .def("rt_roots", [](const GraphHandle& h) { return h.get("rt_roots").rt_roots(); })
      .def("rt_edge", [](const GraphHandle& h, py::handle n) -> py::object {
             Graph& g = h.get("rt_edge");
             auto e = g.rt_edge(to_node(g, n));
             if (!e) return py::none();
             return py::make_tuple(e->parent, pose_to_matrix(e->pose), e->stamp);
           }, py::arg("child"), "(parent, X_PC as a 4x4 array, stamp) of the child's RT edge, or None.")
      .def("subscribe", [](const GraphHandle& h, py::function cb, const std::vector<std::string>& node_types,
                           const std::vector<std::string>& edge_types, const std::vector<std::string>& attributes) {
             return h.get("subscribe").subscribe(to_filter(node_types, edge_types, attributes),
                                                 make_callback<ChangeBatch>(std::move(cb), h.owner));
           }, py::arg("callback"), py::kw_only(), py::arg("node_types") = std::vector<std::string>{},
           py::arg("edge_types") = std::vector<std::string>{}, py::arg("attributes") = std::vector<std::string>{},
           "Calls callback(ChangeBatch) after every commit and merge that changed something (on the graph's "
           "owner thread, with the GIL), with the part the filter selects (node changes of node_types, edge "
           "changes of edge_types, changes naming one of attributes; no filter: everything; an empty part is "
           "not delivered). Returns an id for unsubscribe().")
      .def("unsubscribe", [](const GraphHandle& h, std::uint64_t id) { h.get("unsubscribe").unsubscribe(id); },
           py::arg("id"))
      .def("state", [](const GraphHandle& h) { return GraphState{h.get("state").state()}; })
      .def("merge", [](const GraphHandle& h, const GraphState& s) { h.get("merge").merge(s.delta); }, py::arg("state"),
           "Joins another replica's state (idempotent, commutative).")
      .def("digest", [](const GraphHandle& h) { return h.get("digest").digest().hex(); },
           "Hex digest of the whole CRDT state: equal on two replicas iff their states are.")
      .def("check_invariants", [](const GraphHandle& h) { return h.get("check_invariants").check_invariants(); });
}

}  // namespace quiver::python
