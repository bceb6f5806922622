// World files saved: the graph's visible nodes, edges and RT edges written as a world file.

#include <fstream>

#include "quiver/graph/world_file.h"
#include "world_values.h"

namespace quiver::graph {

using internal::json;
using internal::value_to_json;

std::string save_world(const Graph& g) {
  json root = json::object();
  root["quiver_world"] = 1;
  json nodes = json::array();
  for (NodeId id : g.nodes()) {
    json n = json::object();
    n["name"] = g.name_of(id);
    n["type"] = g.type_of(id).str();
    json attrs = json::object();
    for (Symbol a : g.attr_names(id)) attrs[a.str()] = value_to_json(*g.attr(id, a));
    if (!attrs.empty()) n["attrs"] = std::move(attrs);
    nodes.push_back(std::move(n));
  }
  root["nodes"] = std::move(nodes);
  json edges = json::array();
  json rts = json::array();
  for (NodeId id : g.nodes()) {
    for (const EdgeKey& k : g.edges_from(id)) {
      if (k.type == symbols::rt()) {
        auto rt = g.rt_edge(k.to);
        json r = json::object();
        r["parent"] = g.name_of(k.from);
        r["child"] = g.name_of(k.to);
        r["translation"] = rt->pose.translation;
        r["rotation"] = rt->pose.rotation;
        r["stamp"] = rt->stamp;
        rts.push_back(std::move(r));
        continue;
      }
      json e = json::object();
      e["from"] = g.name_of(k.from);
      e["to"] = g.name_of(k.to);
      e["type"] = k.type.str();
      json attrs = json::object();
      for (Symbol a : g.edge_attr_names(k)) attrs[a.str()] = value_to_json(*g.edge_attr(k, a));
      if (!attrs.empty()) e["attrs"] = std::move(attrs);
      edges.push_back(std::move(e));
    }
  }
  root["edges"] = std::move(edges);
  root["rt"] = std::move(rts);
  return root.dump(2) + "\n";
}

Status save_world_file(const Graph& g, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return make_error(ErrorCode::kIo, "save_world_file(): cannot write '" + path + "'");
  out << save_world(g);
  out.close();
  if (!out) return make_error(ErrorCode::kIo, "save_world_file(): writing '" + path + "' failed");
  return {};
}

}  // namespace quiver::graph
