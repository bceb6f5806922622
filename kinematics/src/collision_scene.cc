// The FCL scene: one fcl::CollisionObjectd per shaped node, in a dynamic AABB tree, posed at X_RN.

#include "quiver/kinematics/collision_scene.h"

#include <fcl/broadphase/detail/hierarchy_tree.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <map>

namespace quiver::kinematics {

using graph::NodeId;

namespace {

using Geometry = fcl::CollisionGeometryd;

fcl::Transform3d to_fcl(const Eigen::Isometry3d& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.linear();
  T.translation() = X.translation();
  return T;
}

}  // namespace

struct CollisionScene::Impl {
  using Tree = fcl::detail::HierarchyTree<fcl::AABBd>;
  using Leaf = Tree::NodeType;
  struct Object {
    NodeId id;
    Frame frame;
    Frame root;
    ShapeSpec spec;
    std::shared_ptr<Geometry> geometry;
    std::unique_ptr<fcl::CollisionObjectd> obj;
    Leaf* leaf = nullptr;  ///< in the broad phase
  };

  FrameTree* frames;
  const graph::Graph* g;
  std::uint64_t listener = 0;
  std::unordered_map<NodeId, std::unique_ptr<Object>> objects;
  std::unordered_map<NodeId, std::string> problems;
  // Meshes shared by every object that uses the same file and scale.
  std::map<std::pair<std::string, std::array<double, 3>>, std::weak_ptr<Geometry>> mesh_cache;
  // The broad phase: FCL's dynamic AABB tree, used directly. (FCL's
  // DynamicAABBTreeCollisionManager::update() measures the tree's height on every call, a walk of
  // the whole tree: O(n) per moved object. Updating the tree's leaves ourselves keeps a move at
  // O(log n): remove and re-insert one leaf, plus one incremental rebalancing pass.)
  Tree tree;
  Stats stats;

  void tree_insert(Object* o) { o->leaf = tree.insert(o->obj->getAABB(), o); }
  void tree_remove(Object* o) {
    if (o->leaf) tree.remove(o->leaf);
    o->leaf = nullptr;
  }

  /// Calls f(a, b) for every pair of leaves whose AABBs overlap.
  template <class F>
  static void self_pairs(Leaf* n, F& f) {
    if (n == nullptr || n->isLeaf()) return;
    self_pairs(n->children[0], f);
    self_pairs(n->children[1], f);
    cross_pairs(n->children[0], n->children[1], f);
  }
  template <class F>
  static void cross_pairs(Leaf* a, Leaf* b, F& f) {
    if (!a->bv.overlap(b->bv)) return;
    if (a->isLeaf() && b->isLeaf()) {
      f(static_cast<Object*>(a->data), static_cast<Object*>(b->data));
      return;
    }
    if (b->isLeaf() || (!a->isLeaf() && a->bv.size() > b->bv.size())) {
      cross_pairs(a->children[0], b, f);
      cross_pairs(a->children[1], b, f);
    } else {
      cross_pairs(a, b->children[0], f);
      cross_pairs(a, b->children[1], f);
    }
  }

  Result<std::shared_ptr<Geometry>> build_geometry(const ShapeSpec& s) {
    ++stats.shapes_built;
    switch (s.kind) {
      case ShapeSpec::Kind::kBox:
        return std::shared_ptr<Geometry>(std::make_shared<fcl::Boxd>(s.size));
      case ShapeSpec::Kind::kSphere:
        return std::shared_ptr<Geometry>(std::make_shared<fcl::Sphered>(s.radius));
      case ShapeSpec::Kind::kCylinder:
        return std::shared_ptr<Geometry>(std::make_shared<fcl::Cylinderd>(s.radius, s.length));
      case ShapeSpec::Kind::kCapsule:
        return std::shared_ptr<Geometry>(std::make_shared<fcl::Capsuled>(s.radius, s.length));
      case ShapeSpec::Kind::kMesh: {
        auto key =
            std::make_pair(s.mesh, std::array<double, 3>{s.scale.x(), s.scale.y(), s.scale.z()});
        if (auto it = mesh_cache.find(key); it != mesh_cache.end())
          if (auto shared = it->second.lock()) return shared;
        auto mesh = load_mesh(s.mesh);
        if (!mesh.ok()) return mesh.error();
        auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
        std::vector<fcl::Vector3d> vertices;
        vertices.reserve(mesh->vertices.size());
        for (const auto& v : mesh->vertices) vertices.push_back(v.cwiseProduct(s.scale));
        std::vector<fcl::Triangle> triangles;
        triangles.reserve(mesh->triangles.size());
        for (const auto& t : mesh->triangles) triangles.emplace_back(t[0], t[1], t[2]);
        model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(vertices.size()));
        model->addSubModel(vertices, triangles);
        model->endModel();
        model->computeLocalAABB();
        std::shared_ptr<Geometry> geom = model;
        mesh_cache[key] = geom;
        return geom;
      }
    }
    return make_error(ErrorCode::kInternal, "unknown shape kind");
  }

  void remove(const NodeId& id) {
    problems.erase(id);
    auto it = objects.find(id);
    if (it == objects.end()) return;
    tree_remove(it->second.get());
    objects.erase(it);
  }

  /// (Re)builds a node's object from its attributes. Returns the new object (not yet registered)
  /// or null when the node has no valid shape.
  Object* make(const NodeId& id) {
    problems.erase(id);
    auto spec = read_shape(*g, id);
    if (!spec.ok()) {
      problems[id] = spec.error().message;
      return nullptr;
    }
    if (!spec->has_value()) return nullptr;
    auto geom = build_geometry(**spec);
    if (!geom.ok()) {
      problems[id] = geom.error().message;
      return nullptr;
    }
    auto o = std::make_unique<Object>();
    o->id = id;
    o->frame = frames->frame_of(id);
    o->root = frames->root_of(o->frame);
    o->spec = **spec;
    o->geometry = *geom;
    auto X = frames->root_pose_of(o->frame);
    o->obj = std::make_unique<fcl::CollisionObjectd>(
        o->geometry, to_fcl(X ? *X : Eigen::Isometry3d::Identity()));
    o->obj->setUserData(o.get());
    o->obj->computeAABB();
    Object* raw = o.get();
    objects[id] = std::move(o);
    return raw;
  }

  void rebuild_all() {
    tree.clear();
    objects.clear();
    problems.clear();
    for (const NodeId& id : g->nodes())
      if (Object* o = make(id)) tree_insert(o);
    tree.balanceTopdown();
    ++stats.full_rebuilds;
  }

  void on_update(const FrameUpdate& u) {
    if (u.resynced) {
      rebuild_all();
      return;
    }
    for (const NodeId& id : u.removed) remove(id);
    if (u.batch) {
      for (const graph::NodeChange& nc : u.batch->nodes) {
        bool rebuild = nc.kind == graph::ChangeKind::kCreated;
        if (nc.kind == graph::ChangeKind::kUpdated)
          for (const graph::Symbol& a : nc.attrs)
            if (shape_attr::is_shape_attr(a.str())) rebuild = true;
        if (nc.kind == graph::ChangeKind::kDeleted) {
          remove(nc.id);
          continue;
        }
        if (!rebuild || !g->has_node(nc.id)) continue;
        remove(nc.id);
        if (Object* o = make(nc.id)) tree_insert(o);
      }
    }
    // Moved frames: new transform and AABB, and their leaves alone re-inserted.
    std::size_t moved = 0;
    for (const Frame& f : u.moved) {
      const NodeId id = frames->node_of(f);
      auto it = objects.find(id);
      if (it == objects.end()) continue;
      Object& o = *it->second;
      auto X = frames->root_pose_of(f);
      if (!X) continue;
      o.frame = f;
      o.root = frames->root_of(f);
      o.obj->setTransform(to_fcl(*X));
      o.obj->computeAABB();  // setTransform() does not refresh the AABB
      if (o.leaf) tree.update(o.leaf, o.obj->getAABB());
      ++moved;
    }
    if (moved > 0) {
      // One rebalancing pass per moved leaf (O(log n) each) keeps the tree's depth in check.
      tree.balanceIncremental(static_cast<int>(std::min<std::size_t>(moved, 64)));
      stats.objects_updated += moved;
      ++stats.broadphase_updates;
    }
  }

  /// The object of a frame reference, or an error saying why there is none.
  Result<Object*> object(const char* fn, const FrameRef& f) {
    auto fr = frames->frame(f);
    if (!fr.ok()) {
      Error e = fr.error();
      e.message = std::string(fn) + "(): " + f.describe() + " does not exist in the frame tree";
      return e;
    }
    const NodeId id = frames->node_of(*fr);
    if (auto p = problems.find(id); p != problems.end())
      return make_error(ErrorCode::kInvalidArgument,
                        std::string(fn) + "(): " + f.describe() +
                            " has an invalid collision shape: " + p->second);
    auto it = objects.find(id);
    if (it == objects.end())
      return make_error(
          ErrorCode::kInvalidArgument,
          std::string(fn) + "(): " + f.describe() + " has no collision shape (attribute 'shape')");
    return it->second.get();
  }

  Status same_tree(const char* fn, const Object& a, const Object& b, const FrameRef& A,
                   const FrameRef& B) {
    if (a.root == b.root) return Status::Ok();
    return make_error(ErrorCode::kNotConnected,
                      std::string(fn) + "(): " + A.describe() + " and " + B.describe() +
                          " are not part of the same tree: they share no frame");
  }
};

CollisionScene::CollisionScene(FrameTree& frames) : impl_(std::make_unique<Impl>()) {
  impl_->frames = &frames;
  impl_->g = &frames.graph();
  impl_->rebuild_all();
  impl_->listener = frames.add_listener([this](const FrameUpdate& u) { impl_->on_update(u); });
}

CollisionScene::~CollisionScene() { impl_->frames->remove_listener(impl_->listener); }

std::size_t CollisionScene::object_count() const { return impl_->objects.size(); }

std::vector<std::pair<NodeId, std::string>> CollisionScene::problems() const {
  std::vector<std::pair<NodeId, std::string>> out(impl_->problems.begin(), impl_->problems.end());
  std::sort(out.begin(), out.end());
  return out;
}

CollisionScene::Stats CollisionScene::stats() const {
  Stats s = impl_->stats;
  s.objects = impl_->objects.size();
  return s;
}

Result<CollisionInfo> CollisionScene::collide(FrameRef A, FrameRef B) {
  auto a = impl_->object("collide", A);
  if (!a.ok()) return a.error();
  auto b = impl_->object("collide", B);
  if (!b.ok()) return b.error();
  if (Status s = impl_->same_tree("collide", **a, **b, A, B); !s.ok()) return s.error();
  fcl::CollisionRequestd req(/*num_max_contacts=*/16, /*enable_contact=*/true);
  fcl::CollisionResultd res;
  fcl::collide((*a)->obj.get(), (*b)->obj.get(), req, res);
  CollisionInfo info;
  info.in_collision = res.isCollision();
  if (info.in_collision && res.numContacts() > 0) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < res.numContacts(); ++i)
      if (res.getContact(i).penetration_depth > res.getContact(best).penetration_depth) best = i;
    const auto& c = res.getContact(best);
    // FCL reports contacts in the common (root) frame; express them in frame A.
    const Eigen::Isometry3d X_RA = *impl_->frames->root_pose_of((*a)->frame);
    info.penetration_depth = c.penetration_depth;
    info.p_AoC_A = X_RA.inverse() * c.pos;
    // FCL's normal points from o1 to o2 (A to B).
    info.n_A = X_RA.linear().transpose() * c.normal;
  }
  return info;
}

Result<DistanceInfo> CollisionScene::distance(FrameRef A, FrameRef B) {
  auto a = impl_->object("distance", A);
  if (!a.ok()) return a.error();
  auto b = impl_->object("distance", B);
  if (!b.ok()) return b.error();
  if (Status s = impl_->same_tree("distance", **a, **b, A, B); !s.ok()) return s.error();
  fcl::DistanceRequestd req(/*enable_nearest_points=*/true);
  fcl::DistanceResultd res;
  fcl::distance((*a)->obj.get(), (*b)->obj.get(), req, res);
  DistanceInfo info;
  const Eigen::Isometry3d X_AR = impl_->frames->root_pose_of((*a)->frame)->inverse();
  if (res.min_distance <= 0.0) {
    // Touching or overlapping: FCL's nearest points are not meaningful; report a contact point.
    info.in_collision = true;
    info.distance = 0.0;
    auto c = collide(A, B);
    if (c.ok() && c->in_collision) info.p_AoPa_A = info.p_AoPb_A = c->p_AoC_A;
    return info;
  }
  info.distance = res.min_distance;
  // FCL 0.7 reports nearest points in the common (root) frame.
  info.p_AoPa_A = X_AR * res.nearest_points[0];
  info.p_AoPb_A = X_AR * res.nearest_points[1];
  return info;
}

std::vector<std::pair<NodeId, NodeId>> CollisionScene::colliding_pairs() {
  std::vector<std::pair<NodeId, NodeId>> out;
  auto narrow = [&](Impl::Object* a, Impl::Object* b) {
    if (!(a->root == b->root)) return;  // different trees: no common frame
    fcl::CollisionRequestd req;
    fcl::CollisionResultd res;
    fcl::collide(a->obj.get(), b->obj.get(), req, res);
    if (res.isCollision()) out.emplace_back(std::min(a->id, b->id), std::max(a->id, b->id));
  };
  Impl::self_pairs(impl_->tree.getRoot(), narrow);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Result<ReachInfo> CollisionScene::within_reach(FrameRef target, FrameRef base, double reach) {
  if (!(reach >= 0.0) || !std::isfinite(reach))
    return make_error(
        ErrorCode::kInvalidArgument,
        "within_reach(): the reach must be a non-negative length, not " + std::to_string(reach));
  auto fb = impl_->frames->frame(base);
  if (!fb.ok()) return fb.error();
  auto ft = impl_->frames->frame(target);
  if (!ft.ok()) return ft.error();
  const NodeId tid = impl_->frames->node_of(*ft);
  if (auto p = impl_->problems.find(tid); p != impl_->problems.end())
    return make_error(
        ErrorCode::kInvalidArgument,
        "within_reach(): " + target.describe() + " has an invalid collision shape: " + p->second);
  if (!(impl_->frames->root_of(*fb) == impl_->frames->root_of(*ft)))
    return make_error(ErrorCode::kNotConnected, "within_reach(): " + target.describe() + " and " +
                                                    base.describe() +
                                                    " are not part of the same tree");
  const Eigen::Isometry3d X_RB = *impl_->frames->root_pose_of(*fb);
  ReachInfo info;
  auto it = impl_->objects.find(tid);
  if (it == impl_->objects.end()) {
    // No shape: the target is its frame's origin.
    const Eigen::Vector3d p_BoT_B =
        X_RB.inverse() * impl_->frames->root_pose_of(*ft)->translation();
    info.p_BoN_B = p_BoT_B;
    info.distance = p_BoT_B.norm();
  } else {
    // The distance from the base origin to the shape: a point-sized sphere at the origin.
    constexpr double kPoint = 1e-9;
    auto probe_geom = std::make_shared<fcl::Sphered>(kPoint);
    fcl::CollisionObjectd probe(probe_geom, to_fcl(X_RB));
    probe.computeAABB();
    fcl::DistanceRequestd req(/*enable_nearest_points=*/true);
    fcl::DistanceResultd res;
    fcl::distance(&probe, it->second->obj.get(), req, res);
    if (res.min_distance <= 0.0) {
      info.distance = 0.0;
      info.p_BoN_B = Eigen::Vector3d::Zero();
    } else {
      info.distance = res.min_distance + kPoint;
      info.p_BoN_B = X_RB.inverse() * res.nearest_points[1];
    }
  }
  info.reachable = info.distance <= reach;
  return info;
}

}  // namespace quiver::kinematics
