// Workloads by name: the seeded operations the simulator's agents commit.
#include "quiver/sim/workload.h"

#include <array>
#include <cmath>

namespace quiver::sim {
namespace {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

const std::array<const char*, 4> kTypes = {"robot", "person", "room", "object"};
const std::array<const char*, 5> kAttrs = {"x", "label", "battery", "pos", "count"};
const std::array<const char*, 4> kEdgeTypes = {"in", "is_with", "sees", "speaking"};

Value random_value(Rng& rng) {
  switch (rng.below(5)) {
    case 0: return Value(rng.uniform());
    case 1: return Value("v" + std::to_string(rng.below(1000)));
    case 2: return Value::int32(static_cast<std::int32_t>(rng.range(-50, 50)));
    case 3: return Value(graph::Vec3f{static_cast<float>(rng.uniform()), 1.0f, 2.0f});
    default: return Value(rng.chance(0.5));
  }
}

graph::Pose random_pose(Rng& rng) {
  graph::Pose p;
  p.translation = {rng.uniform(), rng.uniform(), rng.uniform()};
  double a = rng.uniform() * 3.0;
  p.rotation = {std::cos(a / 2), 0.0, 0.0, std::sin(a / 2)};
  return p;
}

}  // namespace

int Churn::step(graph::Graph& g, Rng& rng, std::int64_t now) {
  auto tx = g.begin();
  std::vector<NodeId> nodes = g.nodes();
  if (!mix_.spare_type.empty()) {
    const graph::Symbol spare(mix_.spare_type);
    std::erase_if(nodes, [&](NodeId n) { return g.type_of(n) == spare; });
  }
  const int total = mix_.create_node + mix_.delete_node + mix_.set_attr + mix_.remove_attr + mix_.insert_edge +
                    mix_.delete_edge + mix_.set_edge_attr + mix_.rt_move + mix_.rt_pose + mix_.rt_remove;
  const int nops = 1 + static_cast<int>(rng.below(mix_.max_ops_per_txn));
  for (int i = 0; i < nops; ++i) {
    int pick = static_cast<int>(rng.below(total));
    auto take = [&](int w) {
      bool hit = pick < w;
      pick -= w;
      return hit;
    };
    if (take(mix_.create_node) || nodes.empty()) {
      if (static_cast<int>(nodes.size()) >= mix_.max_nodes) continue;
      std::string name = rng.chance(0.15) && mix_.shared_names > 0
                             ? "shared" + std::to_string(rng.below(mix_.shared_names))
                             : "n" + std::to_string(g.replica().agent % 1000) + "_" +
                                   std::to_string(g.replica().incarnation) + "_" + std::to_string(names_++);
      std::vector<std::pair<Symbol, Value>> attrs;
      if (rng.chance(0.5)) attrs.emplace_back(Symbol(kAttrs[rng.below(kAttrs.size())]), random_value(rng));
      auto id = tx.create_node(kTypes[rng.below(kTypes.size())], name, std::move(attrs));
      if (id.ok()) nodes.push_back(*id);
      continue;
    }
    const NodeId a = rng.pick(nodes);
    const NodeId b = rng.pick(nodes);
    if (take(mix_.delete_node)) {
      if (tx.delete_node(a).ok()) std::erase(nodes, a);
    } else if (take(mix_.set_attr)) {
      // A value of another type than the attribute holds is written as DSR would have it: removed
      // first (a write alone never changes an attribute's type), so types still change and clash.
      const Symbol attr(kAttrs[rng.below(kAttrs.size())]);
      Value v = random_value(rng);
      if (Status s = tx.set(a, attr, v); !s.ok() && s.error().code == ErrorCode::kTypeMismatch)
        if (tx.remove_attr(a, attr).ok()) (void)tx.set(a, attr, std::move(v));
    } else if (take(mix_.remove_attr)) {
      (void)tx.remove_attr(a, Symbol(kAttrs[rng.below(kAttrs.size())]));
    } else if (take(mix_.insert_edge)) {
      (void)tx.insert_edge(a, b, Symbol(kEdgeTypes[rng.below(kEdgeTypes.size())]));
    } else if (take(mix_.delete_edge)) {
      auto out = g.edges_from(a);
      if (!out.empty()) {
        const auto& k = rng.pick(out);
        if (k.type == graph::symbols::rt()) (void)tx.remove_rt(k.to);
        else (void)tx.delete_edge(k.from, k.to, k.type);
      }
    } else if (take(mix_.set_edge_attr)) {
      auto out = g.edges_from(a);
      if (!out.empty()) {
        const auto& k = rng.pick(out);
        if (k.type != graph::symbols::rt()) {
          Value v = random_value(rng);
          if (Status s = tx.set_edge_attr(k, Symbol("w"), v); !s.ok() && s.error().code == ErrorCode::kTypeMismatch)
            if (tx.remove_edge_attr(k, Symbol("w")).ok()) (void)tx.set_edge_attr(k, Symbol("w"), std::move(v));
        }
      }
    } else if (take(mix_.rt_move)) {
      (void)tx.set_rt(a, b, random_pose(rng), now);
    } else if (take(mix_.rt_pose)) {
      if (auto p = g.rt_parent(a)) (void)tx.set_rt(*p, a, random_pose(rng), now + static_cast<std::int64_t>(rng.below(1000)));
    } else {
      (void)tx.remove_rt(a);
    }
  }
  int n = static_cast<int>(tx.size());
  auto r = tx.commit();
  return r.ok() ? n : 0;
}

}  // namespace quiver::sim
