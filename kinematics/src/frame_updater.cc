// FrameTree's updates: the owner's copy brought up to date with the graph (the Updater: frames
// allocated and freed, RT edges and their samples re-read, names refreshed, root poses
// recomputed for changed subtrees), by a whole sync, per change batch, or by an audit.

#include <algorithm>
#include <span>
#include <stdexcept>
#include <unordered_set>

#include "frame_keys.h"
#include "frame_owner.h"
#include "frame_store.h"
#include "pose_math.h"
#include "quiver/kinematics/frames.h"

namespace quiver::kinematics {

using graph::NodeId;
using internal::kNone;
using internal::Node;
using internal::QP;
using internal::Sample;
using internal::TableOp;
using internal::base_name;
using internal::hash_id;
using internal::hash_name;
using internal::same_values;

namespace {

/// The samples lookups interpolate: the current epoch's history plus the current pose, at most
/// one per stamp (the greatest by (stamp, dot), as the graph orders them).
void build_samples(const graph::RtEdge& e, std::span<const graph::RtSample> hist,
                   std::vector<Sample>& out) {
  out.clear();
  for (const graph::RtSample& s : hist) {
    if (!(s.epoch == e.epoch)) continue;
    Sample x{s.stamp, internal::from_pose(s.pose)};
    if (!out.empty() && out.back().stamp == s.stamp)
      out.back() = x;  // ascending: the later wins
    else
      out.push_back(x);
  }
  // The current pose is the greatest sample of its epoch (or the move's own pose).
  Sample cur{e.stamp, internal::from_pose(e.pose)};
  auto it = std::lower_bound(out.begin(), out.end(), e.stamp,
                             [](const Sample& s, Time t) { return s.stamp < t; });
  if (it != out.end() && it->stamp == e.stamp)
    *it = cur;
  else
    out.insert(it, cur);
}

/// Owner-side operations on the master copy; kept out of the class to keep the header small.
class Updater {
 public:
  Updater(const graph::Graph& g, FrameTree::Owner& o) : g_(g), o_(o), rt_dirty_(o.rt_dirty) {
    rt_dirty_.clear();
  }

  std::int32_t slot_of(const NodeId& id) const {
    auto it = o_.by_id.find(id);
    return it == o_.by_id.end() ? kNone : it->second;
  }

  /// The slot of a visible node, allocated on first sight.
  std::int32_t ensure(const NodeId& id) {
    std::int32_t s = slot_of(id);
    if (s != kNone) return s;
    if (!o_.free_slots.empty()) {
      s = o_.free_slots.back();
      o_.free_slots.pop_back();
    } else {
      if (o_.nodes.size() >= internal::kMaxSlots)
        throw std::length_error("FrameTree: too many frames");
      s = static_cast<std::int32_t>(o_.nodes.size());
      o_.nodes.emplace_back();
    }
    Node& n = o_.nodes[s];
    n.id = id;
    n.live = true;
    n.parent = kNone;
    n.children.clear();
    n.X_PN = QP{};
    n.stamp = 0;
    n.samples.clear();
    n.hist_dirty = true;
    n.world_dirty = false;
    n.root = kNone;  // forces a version bump on first computation
    o_.by_id.emplace(id, s);
    o_.ids.ops.push_back(TableOp{true, hash_id(id), static_cast<std::uint32_t>(s)});
    ++o_.ids.live;
    names_to_refresh_.insert(base_name(g_.name_of(id)));
    mark_world(s);
    o_.touch(s);
    return s;
  }

  void remove(std::int32_t s) {
    Node& n = o_.nodes[s];
    if (!n.live) return;
    unlink(s);
    for (std::int32_t c : n.children) {
      o_.nodes[c].parent = kNone;
      rt_dirty_.push_back(o_.nodes[c].id);
      mark_world(c);
    }
    n.children.clear();
    names_to_refresh_.insert(base_name(n.name));
    set_name(s, std::string());
    o_.ids.ops.push_back(TableOp{false, hash_id(n.id), static_cast<std::uint32_t>(s)});
    --o_.ids.live;
    o_.by_id.erase(n.id);
    o_.removed.push_back(n.id);
    n.live = false;
    ++n.generation;
    if (n.generation == 0) n.generation = 1;
    n.samples.clear();
    n.hist_dirty = true;
    n.world_dirty = false;
    o_.touch(s);
    o_.free_slots.push_back(s);
  }

  void note_rt_change(const NodeId& child) { rt_dirty_.push_back(child); }

  /// Does the owner's copy of frame `s` differ from the graph (its edge or samples)? Names are
  /// kept by the create / delete events of their namesakes.
  bool differs(std::int32_t s) {
    const Node& n = o_.nodes[s];
    if (!g_.has_node(n.id)) return true;
    const auto e = g_.rt_edge(n.id);  // none exactly when the node has no parent
    const std::int32_t ps = e ? slot_of(e->parent) : kNone;
    if (ps != n.parent || (e && ps == kNone)) return true;
    if (!e) return !n.samples.empty() || n.stamp != 0;
    const QP X = internal::from_pose(e->pose);
    if (e->stamp != n.stamp || !same_values(X, n.X_PN)) return true;
    std::vector<Sample>& want = o_.samples;
    build_samples(*e, g_.rt_history(n.id), want);
    if (want.size() != n.samples.size()) return true;
    for (std::size_t i = 0; i < want.size(); ++i)
      if (!same_values(want[i], n.samples[i])) return true;
    return false;
  }

  /// Compares up to `count` live frames with the graph, round robin, and queues repairs.
  std::size_t audit(std::size_t count) {
    std::size_t repaired = 0;
    const std::size_t total = o_.nodes.size();
    for (std::size_t seen = 0; seen < total && count > 0; ++seen) {
      const std::int32_t s = static_cast<std::int32_t>(o_.audit_cursor++ % total);
      const Node& n = o_.nodes[s];
      if (!n.live) continue;
      --count;
      if (!differs(s)) continue;
      ++repaired;
      if (!g_.has_node(n.id)) {
        remove(s);
        continue;
      }
      rt_dirty_.push_back(n.id);
      names_to_refresh_.insert(base_name(g_.name_of(n.id)));
      names_to_refresh_.insert(base_name(n.name));
    }
    return repaired;
  }
  void note_name(const std::string& base) { names_to_refresh_.insert(base); }

  /// Re-reads a child's RT edge from the graph.
  void refresh_edge(const NodeId& id) {
    if (!g_.has_node(id)) return;
    std::int32_t s = ensure(id);
    const auto e = g_.rt_edge(id);  // none exactly when the node has no parent
    std::int32_t ps = e ? ensure(e->parent) : kNone;
    Node& n = o_.nodes[s];
    if (ps != n.parent) {
      unlink(s);
      n.parent = ps;
      if (ps != kNone) o_.nodes[ps].children.push_back(s);
    }
    if (ps != kNone) {
      n.X_PN = internal::from_pose(e->pose);
      n.stamp = e->stamp;
      build_samples(*e, g_.rt_history(id), n.samples);
    } else {
      n.X_PN = QP{};
      n.stamp = 0;
      n.samples.clear();
    }
    n.hist_dirty = true;
    o_.touch(s);
    mark_world(s);
  }

  /// Applies queued edge and name refreshes, then recomputes the dirty root poses.
  void finish() {
    // Each queued child once, in queue order (refresh_edge() queues nothing more).
    std::unordered_set<NodeId>& seen = o_.rt_seen;
    seen.clear();
    for (const NodeId& id : rt_dirty_)
      if (seen.insert(id).second) refresh_edge(id);
    rt_dirty_.clear();
    refresh_names();
    recompute_world();
  }

 private:
  void unlink(std::int32_t s) {
    Node& n = o_.nodes[s];
    if (n.parent == kNone) return;
    auto& sib = o_.nodes[n.parent].children;
    auto it = std::find(sib.begin(), sib.end(), s);
    if (it != sib.end()) {
      *it = sib.back();
      sib.pop_back();
    }
    n.parent = kNone;
  }

  void mark_world(std::int32_t s) { o_.world_dirty_roots.push_back(s); }

  void set_name(std::int32_t s, std::string name) {
    Node& n = o_.nodes[s];
    if (name == n.name && n.live) return;
    if (!n.name.empty()) {
      auto it = o_.by_name.find(n.name);
      if (it != o_.by_name.end() && it->second == s) {
        o_.by_name.erase(it);
        o_.names.ops.push_back(TableOp{false, hash_name(n.name), static_cast<std::uint32_t>(s)});
        --o_.names.live;
      }
    }
    n.name = std::move(name);
    o_.touch(s);
  }

  void refresh_names() {
    // Two passes: drop stale names first, so that swapped names never collide.
    std::vector<std::pair<std::int32_t, std::string>> want;
    for (const std::string& base : names_to_refresh_) {
      if (base.empty()) continue;
      for (const NodeId& id : g_.namesakes(base)) {
        std::int32_t s = slot_of(id);
        if (s == kNone) continue;
        std::string eff = g_.name_of(id);
        if (eff != o_.nodes[s].name) {
          set_name(s, std::string());
          want.emplace_back(s, std::move(eff));
        }
      }
    }
    for (auto& [s, eff] : want) {
      Node& n = o_.nodes[s];
      n.name = eff;
      auto [it, fresh] = o_.by_name.emplace(eff, s);
      if (!fresh) {
        // Another slot still holds this name (it will be refreshed too): take it over.
        o_.names.ops.push_back(
            TableOp{false, hash_name(eff), static_cast<std::uint32_t>(it->second)});
        o_.nodes[it->second].name.clear();
        o_.touch(it->second);
        it->second = s;
        --o_.names.live;
      }
      o_.names.ops.push_back(TableOp{true, hash_name(eff), static_cast<std::uint32_t>(s)});
      ++o_.names.live;
    }
    names_to_refresh_.clear();
  }

  void recompute_world() {
    auto& nodes = o_.nodes;
    // Mark every live node under a dirty root (a node already marked has its subtree marked).
    std::vector<std::int32_t>& marked = o_.marked;
    std::vector<std::int32_t>& stack = o_.stack;
    marked.clear();
    stack.clear();
    for (std::int32_t r : o_.world_dirty_roots) {
      if (!nodes[r].live || nodes[r].world_dirty) continue;
      stack.push_back(r);
      while (!stack.empty()) {
        std::int32_t s = stack.back();
        stack.pop_back();
        Node& n = nodes[s];
        if (n.world_dirty) continue;
        n.world_dirty = true;
        marked.push_back(s);
        for (std::int32_t c : n.children) stack.push_back(c);
      }
    }
    o_.world_dirty_roots.clear();
    // Compute each marked node after its parent.
    std::vector<std::int32_t>& path = o_.path;
    for (std::int32_t s : marked) {
      path.clear();
      for (std::int32_t x = s; x != kNone && nodes[x].world_dirty; x = nodes[x].parent)
        path.push_back(x);
      for (auto it = path.rbegin(); it != path.rend(); ++it) compute(*it);
    }
    o_.stats.pose_recomputes += marked.size();
  }

  void compute(std::int32_t s) {
    Node& n = o_.nodes[s];
    double R[9], p[3];
    std::int32_t root;
    std::uint32_t depth;
    if (n.parent == kNone) {
      static constexpr double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      std::copy(I, I + 9, R);
      p[0] = p[1] = p[2] = 0.0;
      root = s;
      depth = 0;
    } else {
      const Node& par = o_.nodes[n.parent];
      double R_PN[9];
      internal::quat_to_matrix(n.X_PN.q, R_PN);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
          R[i * 3 + j] = par.R_RN[i * 3 + 0] * R_PN[0 * 3 + j] +
                         par.R_RN[i * 3 + 1] * R_PN[1 * 3 + j] +
                         par.R_RN[i * 3 + 2] * R_PN[2 * 3 + j];
        p[i] = par.R_RN[i * 3 + 0] * n.X_PN.p[0] + par.R_RN[i * 3 + 1] * n.X_PN.p[1] +
               par.R_RN[i * 3 + 2] * n.X_PN.p[2] + par.p_RN[i];
      }
      root = par.root;
      depth = par.depth + 1;
    }
    bool changed = root != n.root || depth != n.depth || !std::equal(R, R + 9, n.R_RN) ||
                   !std::equal(p, p + 3, n.p_RN);
    n.world_dirty = false;
    if (!changed) return;
    std::copy(R, R + 9, n.R_RN);
    std::copy(p, p + 3, n.p_RN);
    n.root = root;
    n.depth = depth;
    ++n.version;
    o_.touch(s);
    o_.moved.push_back(Frame{static_cast<std::uint32_t>(s), n.generation});
  }

  const graph::Graph& g_;
  FrameTree::Owner& o_;
  std::vector<NodeId>& rt_dirty_;  // o_.rt_dirty
  std::unordered_set<std::string> names_to_refresh_;
};

}  // namespace

void FrameTree::sync() {
  Owner& o = *own_;
  Updater up(*g_, o);
  // Forget frames whose nodes are gone, then (re)read every visible node's edge.
  std::vector<std::int32_t> gone;
  for (const auto& [id, s] : o.by_id)
    if (!g_->has_node(id)) gone.push_back(s);
  for (std::int32_t s : gone) up.remove(s);
  for (const NodeId& id : g_->nodes()) {
    up.ensure(id);
    up.note_rt_change(id);
    up.note_name(base_name(g_->name_of(id)));
  }
  // Re-derive names from scratch.
  for (auto& n : o.nodes)
    if (n.live) n.name.clear();
  o.by_name.clear();
  o.names.live = 0;
  o.names.rebuild = true;
  o.names.ops.clear();
  up.finish();
  ++o.stats.resyncs;
  // Everything may have changed: publish every live slot.
  for (std::size_t s = 0; s < o.nodes.size(); ++s)
    if (o.nodes[s].live) o.touch(static_cast<std::int32_t>(s));
  FrameUpdate u;
  u.resynced = true;
  publish(u);
}

void FrameTree::on_batch(const graph::ChangeBatch& b) {
  Owner& o = *own_;
  Updater up(*g_, o);
  bool any = false;
  for (const graph::NodeChange& nc : b.nodes) {
    if (nc.kind == graph::ChangeKind::kCreated) {
      if (g_->has_node(nc.id)) {
        up.ensure(nc.id);
        up.note_rt_change(nc.id);
        any = true;
      }
    } else if (nc.kind == graph::ChangeKind::kDeleted) {
      std::int32_t s = up.slot_of(nc.id);
      if (s != kNone) {
        up.remove(s);
        any = true;
      }
    }
  }
  for (const graph::EdgeChange& ec : b.edges) {
    if (ec.key.type != graph::symbols::rt()) continue;
    up.note_rt_change(ec.key.to);
    any = true;
  }
  if (any) up.finish();
  if (o.audit_per_batch > 0) {
    const std::size_t repaired = up.audit(o.audit_per_batch);
    o.stats.repairs += repaired;
    if (repaired > 0) {
      up.finish();
      any = true;
    }
  }
  FrameUpdate u;
  u.batch = &b;
  if (any)
    publish(u);
  else
    o.notify(u);
}

std::size_t FrameTree::audit(std::size_t frames) {
  Owner& o = *own_;
  Updater up(*g_, o);
  const std::size_t repaired = up.audit(frames);
  o.stats.repairs += repaired;
  if (repaired == 0) return 0;
  up.finish();
  FrameUpdate u;
  publish(u);
  return repaired;
}

}  // namespace quiver::kinematics
