// The FCL scene: one fcl::CollisionObjectd per shaped node, in a dynamic AABB tree, posed at X_RN.

#include "quiver/kinematics/collision_scene.h"

#include <fcl/broadphase/detail/hierarchy_tree.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <map>
#include <type_traits>

namespace quiver::kinematics {

using graph::NodeId;

namespace {

using Geometry = fcl::CollisionGeometryd;
// FCL's transforms are Eigen isometries: poses are passed as they are.
static_assert(std::is_same_v<fcl::Transform3d, Eigen::Isometry3d>);

}  // namespace

struct CollisionScene::Impl {
  using Tree = fcl::detail::HierarchyTree<fcl::AABBd>;
  using Leaf = Tree::NodeType;
  struct Object {
    NodeId id;
    Frame frame;
    Frame root;
    std::unique_ptr<fcl::CollisionObjectd> obj;  ///< holds the geometry
    Leaf* leaf = nullptr;                        ///< in the broad phase
    std::uint64_t built = 0;                     ///< the update (see `updates`) that built it
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
  std::uint64_t updates = 0;  ///< on_update() calls so far

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
    o->built = updates;
    auto X = frames->root_pose_of(o->frame);
    o->obj = std::make_unique<fcl::CollisionObjectd>(*geom, X ? *X : Eigen::Isometry3d::Identity());
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
    ++updates;
    if (u.resynced) {
      rebuild_all();
      return;
    }
    // Removed frames: the frame tree lists every deleted node it knew, and it knows every node
    // the scene has built an object for, so the batch's kDeleted events need nothing more.
    for (const NodeId& id : u.removed) remove(id);
    if (u.batch) {
      for (const graph::NodeChange& nc : u.batch->nodes) {
        if (nc.kind == graph::ChangeKind::kDeleted) continue;
        bool rebuild = nc.kind == graph::ChangeKind::kCreated;
        if (nc.kind == graph::ChangeKind::kUpdated)
          for (const graph::Symbol& a : nc.attrs)
            if (shape_attr::is_shape_attr(a.str())) rebuild = true;
        if (!rebuild || !g->has_node(nc.id)) continue;
        remove(nc.id);
        if (Object* o = make(nc.id)) tree_insert(o);
      }
    }
    // Moved frames: new transform and AABB, and their leaves alone re-inserted. An object built
    // above already has its current pose (and counts as updated all the same).
    std::size_t moved = 0;
    for (const Frame& f : u.moved) {
      const NodeId id = frames->node_of(f);
      auto it = objects.find(id);
      if (it == objects.end()) continue;
      Object& o = *it->second;
      auto X = frames->root_pose_of(f);
      if (!X) continue;
      ++moved;
      if (o.built == updates) continue;
      o.frame = f;
      o.root = frames->root_of(f);
      o.obj->setTransform(*X);
      o.obj->computeAABB();  // setTransform() does not refresh the AABB
      if (o.leaf) tree.update(o.leaf, o.obj->getAABB());
    }
    if (moved > 0) {
      // One rebalancing pass per moved leaf (O(log n) each) keeps the tree's depth in check.
      tree.balanceIncremental(static_cast<int>(std::min<std::size_t>(moved, 64)));
      stats.objects_updated += moved;
      ++stats.broadphase_updates;
    }
  }

  /// The object of a live frame, or null if its node has no shape; an error if its shape is
  /// invalid.
  Result<Object*> shape_of(const char* fn, const FrameRef& f, Frame fr) {
    const NodeId id = frames->node_of(fr);
    if (auto p = problems.find(id); p != problems.end())
      return make_error(ErrorCode::kInvalidArgument,
                        std::string(fn) + "(): " + f.describe() +
                            " has an invalid collision shape: " + p->second);
    auto it = objects.find(id);
    return it == objects.end() ? nullptr : it->second.get();
  }

  /// The object of a frame reference, or an error saying why there is none.
  Result<Object*> object(const char* fn, const FrameRef& f) {
    auto fr = frames->frame(f);
    if (!fr.ok()) {
      Error e = fr.error();
      e.message = std::string(fn) + "(): " + f.describe() + " does not exist in the frame tree";
      return e;
    }
    auto o = shape_of(fn, f, *fr);
    if (o.ok() && *o == nullptr)
      return make_error(
          ErrorCode::kInvalidArgument,
          std::string(fn) + "(): " + f.describe() + " has no collision shape (attribute 'shape')");
    return o;
  }

  /// Ok if the roots are the same frame; `detail` ends the error message.
  static Status same_tree(const char* fn, Frame root_a, Frame root_b, const FrameRef& A,
                          const FrameRef& B, const char* detail) {
    if (root_a == root_b) return Status::Ok();
    return make_error(ErrorCode::kNotConnected, std::string(fn) + "(): " + A.describe() + " and " +
                                                    B.describe() +
                                                    " are not part of the same tree" + detail);
  }

  /// The objects of A and B, which must share a tree (collide(), distance()).
  Result<std::pair<Object*, Object*>> object_pair(const char* fn, const FrameRef& A,
                                                  const FrameRef& B) {
    auto a = object(fn, A);
    if (!a.ok()) return a.error();
    auto b = object(fn, B);
    if (!b.ok()) return b.error();
    if (Status s = same_tree(fn, (*a)->root, (*b)->root, A, B, ": they share no frame"); !s.ok())
      return s.error();
    return std::make_pair(*a, *b);
  }

  /// The narrow phase of collide(a, b): the deepest contact, in a's frame.
  CollisionInfo contact(const Object& a, const Object& b) {
    fcl::CollisionRequestd req(/*num_max_contacts=*/16, /*enable_contact=*/true);
    fcl::CollisionResultd res;
    fcl::collide(a.obj.get(), b.obj.get(), req, res);
    CollisionInfo info;
    info.in_collision = res.isCollision();
    if (info.in_collision && res.numContacts() > 0) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < res.numContacts(); ++i)
        if (res.getContact(i).penetration_depth > res.getContact(best).penetration_depth) best = i;
      const auto& c = res.getContact(best);
      // FCL reports contacts in the common (root) frame; express them in frame A.
      const Eigen::Isometry3d X_RA = *frames->root_pose_of(a.frame);
      info.penetration_depth = c.penetration_depth;
      info.p_AoC_A = X_RA.inverse() * c.pos;
      // FCL's normal points from o1 to o2 (A to B).
      info.n_A = X_RA.linear().transpose() * c.normal;
    }
    return info;
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
  auto ab = impl_->object_pair("collide", A, B);
  if (!ab.ok()) return ab.error();
  return impl_->contact(*ab->first, *ab->second);
}

Result<DistanceInfo> CollisionScene::distance(FrameRef A, FrameRef B) {
  auto ab = impl_->object_pair("distance", A, B);
  if (!ab.ok()) return ab.error();
  const Impl::Object& a = *ab->first;
  const Impl::Object& b = *ab->second;
  fcl::DistanceRequestd req(/*enable_nearest_points=*/true);
  fcl::DistanceResultd res;
  fcl::distance(a.obj.get(), b.obj.get(), req, res);
  DistanceInfo info;
  const Eigen::Isometry3d X_AR = impl_->frames->root_pose_of(a.frame)->inverse();
  if (res.min_distance <= 0.0) {
    // Touching or overlapping: FCL's nearest points are not meaningful; report a contact point.
    info.in_collision = true;
    info.distance = 0.0;
    const CollisionInfo c = impl_->contact(a, b);
    if (c.in_collision) info.p_AoPa_A = info.p_AoPb_A = c.p_AoC_A;
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
  auto shape = impl_->shape_of("within_reach", target, *ft);
  if (!shape.ok()) return shape.error();
  if (Status s = Impl::same_tree("within_reach", impl_->frames->root_of(*ft),
                                 impl_->frames->root_of(*fb), target, base, "");
      !s.ok())
    return s.error();
  const Eigen::Isometry3d X_RB = *impl_->frames->root_pose_of(*fb);
  ReachInfo info;
  if (*shape == nullptr) {
    // No shape: the target is its frame's origin.
    const Eigen::Vector3d p_BoT_B =
        X_RB.inverse() * impl_->frames->root_pose_of(*ft)->translation();
    info.p_BoN_B = p_BoT_B;
    info.distance = p_BoT_B.norm();
  } else {
    // The distance from the base origin to the shape: a point-sized sphere at the origin.
    constexpr double kPoint = 1e-9;
    auto probe_geom = std::make_shared<fcl::Sphered>(kPoint);
    fcl::CollisionObjectd probe(probe_geom, X_RB);
    probe.computeAABB();
    fcl::DistanceRequestd req(/*enable_nearest_points=*/true);
    fcl::DistanceResultd res;
    fcl::distance(&probe, (*shape)->obj.get(), req, res);
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
