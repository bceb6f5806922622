// FrameTree, the owner: construction (following a graph or not), readers, listeners, the
// owner-side accessors, and the check of the table against a fresh derivation from the graph.

#include <algorithm>

#include "frame_owner.h"
#include "frame_store.h"
#include "pose_math.h"
#include "quiver/kinematics/frames.h"

namespace quiver::kinematics {

using graph::NodeId;
using internal::Core;
using internal::kNone;
using internal::Node;
using internal::same_values;

FrameTree::FrameTree(graph::Graph& g, FrameTreeOptions options)
    : g_(&g),
      core_(std::make_shared<Core>()),
      own_(std::make_unique<Owner>()),
      self_(core_, false) {
  own_->audit_per_batch = options.audit_per_batch;
  sync();
  if (options.follow) {
    followed_ = &g;
    sub_ = g.subscribe([this](const graph::ChangeBatch& b) { on_batch(b); });
  }
}

FrameTree::FrameTree(const graph::Graph& g)
    : g_(&g),
      core_(std::make_shared<Core>()),
      own_(std::make_unique<Owner>()),
      self_(core_, false) {
  sync();
}

FrameTree::~FrameTree() {
  if (sub_) followed_->unsubscribe(*sub_);
}

FrameReader FrameTree::reader() { return FrameReader(core_, true); }

std::uint64_t FrameTree::add_listener(Listener l) {
  std::uint64_t id = own_->next_listener++;
  own_->listeners.emplace_back(id, std::move(l));
  return id;
}

void FrameTree::remove_listener(std::uint64_t id) {
  auto& v = own_->listeners;
  v.erase(std::remove_if(v.begin(), v.end(), [&](const auto& p) { return p.first == id; }),
          v.end());
}

Frame FrameTree::frame_of(NodeId id) const {
  auto it = own_->by_id.find(id);
  if (it == own_->by_id.end()) return Frame{};
  const Node& n = own_->nodes[it->second];
  return Frame{static_cast<std::uint32_t>(it->second), n.generation};
}

namespace {
const Node* live_node(const std::vector<Node>& nodes, Frame f) {
  if (f.is_null() || f.slot >= nodes.size()) return nullptr;
  const Node& n = nodes[f.slot];
  return n.live && n.generation == f.generation ? &n : nullptr;
}
}  // namespace

std::optional<Eigen::Isometry3d> FrameTree::root_pose_of(Frame f) const {
  const Node* n = live_node(own_->nodes, f);
  if (n == nullptr) return std::nullopt;
  return internal::to_isometry(n->R_RN, n->p_RN);
}

Frame FrameTree::root_of(Frame f) const {
  const Node* n = live_node(own_->nodes, f);
  if (n == nullptr || n->root < 0) return Frame{};
  return Frame{static_cast<std::uint32_t>(n->root), own_->nodes[n->root].generation};
}

NodeId FrameTree::node_of(Frame f) const {
  const Node* n = live_node(own_->nodes, f);
  return n ? n->id : NodeId{};
}

FrameTree::Stats FrameTree::stats() const {
  Stats s = own_->stats;
  s.frames = own_->by_id.size();
  s.retired_pending = core_->retired.size();
  return s;
}

std::vector<std::string> FrameTree::check_against_graph() const {
  std::vector<std::string> out;
  const Owner& o = *own_;
  FrameTree fresh(*g_);
  const Owner& f = *fresh.own_;
  if (o.by_id.size() != f.by_id.size())
    out.push_back("frame count " + std::to_string(o.by_id.size()) +
                  " != " + std::to_string(f.by_id.size()));
  for (const auto& [id, s] : f.by_id) {
    auto it = o.by_id.find(id);
    if (it == o.by_id.end()) {
      out.push_back("missing frame for node " + id.to_string());
      continue;
    }
    const Node& a = o.nodes[it->second];
    const Node& b = f.nodes[s];
    std::string who = "frame \"" + b.name + "\": ";
    if (a.name != b.name) out.push_back(who + "name \"" + a.name + "\"");
    NodeId pa = a.parent == kNone ? NodeId{} : o.nodes[a.parent].id;
    NodeId pb = b.parent == kNone ? NodeId{} : f.nodes[b.parent].id;
    if (!(pa == pb)) out.push_back(who + "parent differs");
    if (!std::equal(a.R_RN, a.R_RN + 9, b.R_RN) || !std::equal(a.p_RN, a.p_RN + 3, b.p_RN))
      out.push_back(who + "cached root pose differs");
    if (a.depth != b.depth) out.push_back(who + "depth differs");
    if (o.nodes[a.root].id != f.nodes[b.root].id) out.push_back(who + "root differs");
    if (a.samples.size() != b.samples.size()) {
      out.push_back(who + "sample count " + std::to_string(a.samples.size()) +
                    " != " + std::to_string(b.samples.size()));
    } else {
      for (std::size_t i = 0; i < a.samples.size(); ++i)
        if (!same_values(a.samples[i], b.samples[i]))
          out.push_back(who + "sample " + std::to_string(i) + " differs: stamp " +
                        std::to_string(a.samples[i].stamp) + " vs " +
                        std::to_string(b.samples[i].stamp) + " x " +
                        std::to_string(a.samples[i].X.p[0]) + " vs " +
                        std::to_string(b.samples[i].X.p[0]) + " (of " +
                        std::to_string(a.samples.size()) + ")");
    }
  }
  for (const auto& [name, s] : f.by_name) {
    auto it = o.by_name.find(name);
    if (it == o.by_name.end() || !(o.nodes[it->second].id == f.nodes[s].id))
      out.push_back("name \"" + name + "\" maps elsewhere");
  }
  if (o.by_name.size() != f.by_name.size()) out.push_back("name count differs");
  return out;
}

}  // namespace quiver::kinematics
