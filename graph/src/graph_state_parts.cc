// States in parts (state_parts.h): encoded from the records a part at a time, and joined a part
// at a time with the phases of Impl::merge_state() of the decoded whole, in the same order.

#include "quiver/graph/state_parts.h"

#include <algorithm>
#include <unordered_set>

#include "graph_impl.h"

namespace quiver::graph {

void encode_state(const Graph& graph, const crdt::CausalContext& theirs, std::vector<std::uint8_t>& out,
                  std::size_t part_ops) {
  const auto& g = GraphAccess::of(graph);  // Graph::Impl
  GraphDelta part;  // one part at a time, its arrays reused from part to part
  part.kind = GraphDelta::Kind::kState;
  part.origin = g.self;
  part.context = g.ctx;
  part_ops = std::max<std::size_t>(part_ops, 1);
  encode_parts(
      [&](PartOps ops, const std::function<void(const GraphDelta&)>& each) {
        part.clear_ops();
        bool sent = false;
        const auto full = [&] {
          if (part.nodes.size() + part.edges.size() < part_ops) return;
          each(part);
          sent = true;
          part.clear_ops();
        };
        if (ops != PartOps::kEdges)
          for (const auto& [id, r] : g.nodes) {
            emit_node(id, r, theirs, part);
            full();
          }
        if (ops != PartOps::kNodes)
          for (const auto& [key, e] : g.edges) {
            emit_edge(key, e, theirs, part);
            full();
          }
        if (!sent || !part.nodes.empty() || !part.edges.empty() || !part.keep.empty()) each(part);
      },
      out);
}

Status merge_state(Graph& graph, std::span<const std::uint8_t> encoded, GraphDelta& scratch, const PartSink& admit,
                   const DecodeLimits& limits, std::size_t part_ops) {
  auto& g = GraphAccess::of(graph);  // Graph::Impl
  // Read and check the whole message first (its new names enter the table only then), and let
  // `admit` see every part: nothing is joined before all of it has passed.
  std::size_t node_ops = 0, edge_ops = 0;
  const auto count = [&](const GraphDelta& p) {
    node_ops += p.nodes.size();
    edge_ops += p.edges.size();
    return Status{};
  };
  if (Status s = decode_parts(encoded, scratch, part_ops, count, limits); !s.ok()) return s;
  if (admit)
    if (Status s = decode_parts(encoded, scratch, part_ops, admit, limits); !s.ok()) return s;
  if (!g.merge_observers.empty()) {
    if (Status s = decode(encoded, scratch, limits); !s.ok()) return s;
    graph.merge(scratch);
    return {};
  }
  ++g.epoch;
  g.begin_tracking();
  if (!g.nodes.empty() || !g.edges.empty()) {
    // Our entries the sender removed go first, as in a whole state's join: the dots it holds
    // are gathered over its parts, and the last part (in `scratch`) carries its context.
    std::unordered_set<Dot> held;
    (void)decode_parts(encoded, scratch, part_ops, [&](const GraphDelta& p) { add_held(p, held); return Status{}; },
                       limits);
    g.remove_unheld(scratch.context, held);
  }
  // A large state grows the tables once, not by rehashing (as merge_ops() of the whole does).
  if (node_ops > 1024) g.nodes.reserve(g.nodes.size() + node_ops);
  if (edge_ops > 1024) g.edges.reserve(g.edges.size() + edge_ops);
  // Dots an entry names outside the message's context (only a forged state has them) enter our
  // context at the end, as a whole state's join adds every dot it mentions.
  std::vector<Dot> outside;
  (void)decode_parts(
      encoded, scratch, part_ops,
      [&](const GraphDelta& p) {
        g.merge_ops(p);
        g.kill_removed_ids(p);
        p.for_each_mentioned_dot([&](const Dot& x) {
          if (!p.context.contains(x)) outside.push_back(x);
        });
        return Status{};
      },
      limits);
  for (const Dot& x : outside) g.ctx.add(x);
  g.after_merge(scratch, true);
  return {};
}

}  // namespace quiver::graph
