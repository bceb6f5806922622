#pragma once
// Reference kinematics for tests: transforms computed the slow, obvious way straight from the
// graph (Eigen products along the chain, Eigen's slerp), independent of the kinematics module.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/base/rng.h"

namespace quiver::kinematics::testing {

using graph::Graph;
using graph::NodeId;
using graph::Pose;

inline Eigen::Isometry3d iso(const Pose& p) {
  Eigen::Quaterniond q(p.rotation[0], p.rotation[1], p.rotation[2], p.rotation[3]);
  q.normalize();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = Eigen::Vector3d(p.translation[0], p.translation[1], p.translation[2]);
  return X;
}

inline Pose random_pose(Rng& rng, double extent = 2.0) {
  Pose p;
  for (auto& t : p.translation) t = (rng.uniform() * 2 - 1) * extent;
  Eigen::Quaterniond q(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1,
                       rng.uniform() * 2 - 1);
  if (q.norm() < 1e-3) q = Eigen::Quaterniond::Identity();
  q.normalize();
  p.rotation = {q.w(), q.x(), q.y(), q.z()};
  return p;
}

/// Is `x` in the RT subtree rooted at `root` (`root` itself included)?
inline bool in_subtree(const Graph& g, NodeId root, NodeId x) {
  for (std::optional<NodeId> c = x; c; c = g.rt_parent(*c))
    if (*c == root) return true;
  return false;
}

/// X_RN by multiplying the current edge transforms from N up to its root R.
inline std::pair<NodeId, Eigen::Isometry3d> ref_root_pose(const Graph& g, NodeId n) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  NodeId cur = n;
  for (int guard = 0; guard < 100000; ++guard) {
    auto e = g.rt_edge(cur);
    if (!e) break;
    X = iso(e->pose) * X;
    cur = e->parent;
  }
  return {cur, X};
}

/// The samples a timed lookup may use on `child`'s edge: the current epoch's history plus the
/// current pose, one per stamp.
struct RefSample {
  std::int64_t stamp;
  Pose pose;
};
inline std::vector<RefSample> ref_samples(const Graph& g, NodeId child) {
  auto e = g.rt_edge(child);
  std::vector<RefSample> out;
  for (const auto& s : g.rt_history(child)) {
    if (!(s.epoch == e->epoch)) continue;
    if (!out.empty() && out.back().stamp == s.stamp)
      out.back() = {s.stamp, s.pose};
    else
      out.push_back({s.stamp, s.pose});
  }
  auto it =
      std::find_if(out.begin(), out.end(), [&](const RefSample& s) { return s.stamp >= e->stamp; });
  if (it != out.end() && it->stamp == e->stamp)
    *it = {e->stamp, e->pose};
  else
    out.insert(it, {e->stamp, e->pose});
  return out;
}

/// X_PC at time t, or nullopt if t is outside the edge's samples.
inline std::optional<Eigen::Isometry3d> ref_edge_at(const Graph& g, NodeId child, std::int64_t t) {
  auto s = ref_samples(g, child);
  if (s.size() == 1) {
    if (t < s[0].stamp) return std::nullopt;
    return iso(s[0].pose);
  }
  if (t < s.front().stamp || t > s.back().stamp) return std::nullopt;
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    if (t == s[i].stamp) return iso(s[i].pose);
    if (t > s[i].stamp && t < s[i + 1].stamp) {
      const double r = double(t - s[i].stamp) / double(s[i + 1].stamp - s[i].stamp);
      const auto& a = s[i].pose;
      const auto& b = s[i + 1].pose;
      Eigen::Quaterniond qa(a.rotation[0], a.rotation[1], a.rotation[2], a.rotation[3]);
      Eigen::Quaterniond qb(b.rotation[0], b.rotation[1], b.rotation[2], b.rotation[3]);
      qa.normalize();
      qb.normalize();
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = qa.slerp(r, qb).normalized().toRotationMatrix();
      for (int k = 0; k < 3; ++k)
        X.translation()[k] = a.translation[k] + r * (b.translation[k] - a.translation[k]);
      return X;
    }
  }
  return iso(s.back().pose);
}

/// X_AB at time t by interpolating every edge from A and from B up to the root.
inline std::optional<Eigen::Isometry3d> ref_lookup_at(const Graph& g, NodeId a, NodeId b,
                                                      std::int64_t t) {
  if (a == b) return Eigen::Isometry3d::Identity();
  auto chain = [&](NodeId n) {
    std::vector<NodeId> v{n};
    while (auto p = g.rt_parent(v.back())) v.push_back(*p);
    return v;
  };
  auto ca = chain(a), cb = chain(b);
  if (!(ca.back() == cb.back())) return std::nullopt;
  // Lowest common ancestor: first node of ca that is also in cb.
  NodeId lca = ca.back();
  for (const NodeId& x : ca)
    if (std::find(cb.begin(), cb.end(), x) != cb.end()) {
      lca = x;
      break;
    }
  auto to_lca = [&](const std::vector<NodeId>& c) -> std::optional<Eigen::Isometry3d> {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    for (const NodeId& n : c) {
      if (n == lca) break;
      auto e = ref_edge_at(g, n, t);
      if (!e) return std::nullopt;
      X = *e * X;
    }
    return X;
  };
  auto X_LA = to_lca(ca), X_LB = to_lca(cb);
  if (!X_LA || !X_LB) return std::nullopt;
  return Eigen::Isometry3d(X_LA->inverse() * *X_LB);
}

inline double max_abs_diff(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

}  // namespace quiver::kinematics::testing
