// The replica simulator's lock and rooms workloads: agents competing for priority locks on a few
// scopes (LockWorkload), and agents moving one robot between rooms under a grammar (RoomsWorkload).
#include "replica_simulation.h"

namespace quiver::sim {

std::string Simulation::rooms_grammar(bool repair) {
  return std::string(
             "grammar rooms\n"
             "types { robot room }\n"
             "allow attributes\n"
             "rule changeRoom : active {\n"
             "  { r:robot a:room b:room  r->a(in)  a->b(transitable) }\n"
             "  =>\n"
             "  { r:robot a:room b:room  r->b(in)  a->b(transitable) }\n"
             "}\n"
             "constraint robotInOneRoom {\n"
             "  forbid { r:robot a:room b:room  r->a(in)  r->b(in) }\n") +
         (repair ? "  repair by agent0: delete oldest\n" : "") + "}\n";
}

// Scope roots, each with two RT children, created by agent 0 before the workload starts.
void Simulation::create_scopes() {
  auto tx = agents_[0].graph->begin();
  for (int s = 0; s < cfg_.locks.scopes; ++s) {
    auto root = tx.create_node("scope", "scope" + std::to_string(s));
    scope_roots_.push_back(*root);
    for (int c = 0; c < 2; ++c) {
      auto child = tx.create_node("part", "scope" + std::to_string(s) + "_part" + std::to_string(c));
      (void)tx.set_rt(*root, *child, graph::Pose{}, 0);
    }
  }
  (void)tx.commit();
}

void Simulation::create_rooms() {
  graph::Graph& g = *agents_[0].graph;
  auto tx = g.begin();
  auto robot = tx.create_node("robot", "robot");
  std::vector<graph::NodeId> rooms;
  for (int i = 0; i < cfg_.rooms.rooms; ++i) rooms.push_back(*tx.create_node("room", "room" + std::to_string(i)));
  for (auto a : rooms)
    for (auto b : rooms)
      if (!(a == b)) (void)tx.insert_edge(a, b, graph::Symbol("transitable"));
  (void)tx.insert_edge(*robot, rooms[0], graph::Symbol("in"));
  // The world is set up before any rule applies.
  g.set_commit_validator(nullptr);
  (void)tx.commit();
  agents_[0].engine->install_checks();
}

// One changeRoom attempt by agent `who`, checked by its grammar.
void Simulation::rooms_step(int who) {
  graph::Graph& g = *agents_[who].graph;
  auto robot = g.find_node("robot");
  if (!robot) return;
  auto in = g.edges_from(*robot, graph::Symbol("in"));
  if (in.empty()) return;
  graph::NodeId from = rng_.pick(in).to;
  auto next = g.edges_from(from, graph::Symbol("transitable"));
  if (next.empty()) return;
  graph::NodeId to = rng_.pick(next).to;
  auto tx = g.begin();
  (void)tx.delete_edge(*robot, from, graph::Symbol("in"));
  (void)tx.insert_edge(*robot, to, graph::Symbol("in"));
  if (tx.commit().ok()) ++result_.moves;
  else ++result_.moves_refused;
}

// One lock action by agent `who`: release, write inside a held scope, or acquire.
void Simulation::lock_step(int who) {
  Agent& a = agents_[who];
  std::vector<graph::NodeId> roots;
  for (graph::NodeId r : scope_roots_)
    if (a.graph->has_node(r)) roots.push_back(r);
  if (roots.empty()) return;
  graph::NodeId root = rng_.pick(roots);
  if (a.locks->holds(root) || a.locks->pending(root)) {
    if (rng_.chance(0.3)) {
      (void)a.locks->release(root);
    } else {
      auto tx = a.graph->begin();
      (void)tx.set(root, graph::Symbol("work"), graph::Value(static_cast<std::int64_t>(net_.now())));
      (void)tx.commit();
    }
    return;
  }
  std::int64_t prio = 1 + static_cast<std::int64_t>(rng_.below(cfg_.locks.max_priority));
  if (rng_.chance(0.15)) {
    // Two scopes at once, in canonical order (no deadlock).
    if (!a.locks->acquire_all({root, rng_.pick(roots)}, prio).ok()) ++result_.lock_refused;
  } else if (!a.locks->acquire(root, prio).ok()) {
    ++result_.lock_refused;
  }
}

}  // namespace quiver::sim
