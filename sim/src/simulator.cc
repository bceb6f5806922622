#include "quiver/sim/simulator.h"

#include <algorithm>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <queue>

#include "quiver/agents/replication/packet_codec.h"
#include "quiver/agents/grammar/grammar_guard.h"
#include "quiver/agents/locks/locks.h"
#include "quiver/rng.h"

namespace quiver::sim {
namespace {

using agents::PeerId;

class Simulation;

struct Agent {
  std::uint64_t agent_id = 0;
  std::uint64_t incarnation = 0;
  bool up = false;
  std::unique_ptr<graph::Graph> graph;
  std::unique_ptr<agents::Replicator> replicator;
  std::unique_ptr<agents::LockManager> locks;
  std::unique_ptr<agents::GrammarGuard> guard;
};

std::string rooms_grammar(bool repair) {
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

class Simulation {
 public:
  explicit Simulation(const SimConfig& cfg)
      : cfg_(cfg), rng_(cfg.seed), net_(cfg.agents, rng_.fork(), cfg.faults) {
    result_.seed = cfg.seed;
    result_.agents = cfg.agents;
    result_.steps = cfg.steps;
    ChurnMix mix = cfg.mix;
    if (cfg.locks.enabled) mix.delete_node = 0;  // keep the scope roots alive
    churn_ = Churn(mix);
    if (cfg.rooms.enabled)
      rooms_grammar_ = *agents::parse_grammar(rooms_grammar(cfg.rooms.repair), "rooms");
    agents_.resize(cfg.agents);
    net_.after_each_event([this] { account_overlap(); });
  }

  SimResult run() {
    for (int i = 0; i < cfg_.agents; ++i) {
      agents_[i].agent_id = 0x5100 + static_cast<std::uint64_t>(i);
      boot(i);
      net_.at(static_cast<std::int64_t>(rng_.below(cfg_.tick_interval_ns)), [this, i] { tick(i); });
    }
    const std::int64_t work_end = cfg_.steps * cfg_.step_interval_ns;
    if (cfg_.locks.enabled) create_scopes();
    if (cfg_.rooms.enabled) create_rooms();
    for (int s = 0; s < cfg_.steps; ++s) net_.at((s + 1) * cfg_.step_interval_ns, [this] { step(); });
    plan_faults(work_end);
    // Workload and faults.
    net_.run_until(work_end + cfg_.step_interval_ns);
    // Heal: faults off, everyone up and connected; then wait for convergence.
    note("workload done (" + std::to_string(result_.ops) + " changes); faults off, partitions healed, crashed agents restart");
    net_.faults().loss = 0;
    net_.faults().dup = 0;
    net_.heal();
    for (int i = 0; i < cfg_.agents; ++i)
      if (!agents_[i].up) boot(i);
    const std::int64_t heal_at = net_.now();
    const std::int64_t deadline = net_.now() + cfg_.settle_limit_ns;
    while (net_.now() < deadline) {
      net_.run_until(net_.now() + 50'000'000);
      if (converged()) {
        result_.converged = true;
        note("converged: " + std::to_string(cfg_.agents) + " replicas hold digest " +
             agents_[0].graph->digest().hex() + " (" + std::to_string(agents_[0].graph->node_count()) + " nodes)");
        break;
      }
    }
    account_overlap();
    result_.settle_ms = (net_.now() - heal_at) / 1'000'000;
    result_.virtual_ms = net_.now() / 1'000'000;
    result_.messages = net_.stats().messages;
    result_.bytes = net_.stats().bytes;
    result_.dropped = net_.stats().dropped;
    result_.duplicated = net_.stats().duplicated;
    check_invariants_all();
    result_.digest = agents_[0].graph->digest().hex();
    result_.final_nodes = agents_[0].graph->node_count();
    result_.final_edges = agents_[0].graph->edge_count();
    for (const auto& a : agents_) add_stats(a);
    if (agents_[0].guard) result_.final_violations = agents_[0].guard->checker().all_violations(*agents_[0].graph).size();
    if (cfg_.inspect) {
      std::vector<const graph::Graph*> graphs;
      for (const auto& a : agents_) graphs.push_back(a.graph.get());
      cfg_.inspect(graphs);
    }
    return result_;
  }

 private:
  void note(const std::string& line) {
    if (cfg_.log) cfg_.log(net_.now(), line);
  }

  void boot(int i) {
    Agent& a = agents_[i];
    if (a.incarnation > 0) note("agent" + std::to_string(i) + " restarts as incarnation " + std::to_string(a.incarnation + 1) + " with an empty replica");
    ++a.incarnation;
    a.up = true;
    a.graph = std::make_unique<graph::Graph>(graph::ReplicaId{a.agent_id, a.incarnation});
    net_.set_up(i, true);
    net_.set_address(i, a.graph->replica());
    agents::ReplicatorOptions opt = cfg_.replicator;
    opt.name = "agent" + std::to_string(i);
    a.replicator = std::make_unique<agents::Replicator>(*a.graph, net_.endpoint(i), opt);
    net_.set_receiver(i, [this, i](std::span<const std::uint8_t> packet, std::int64_t now) {
      agents_[i].replicator->on_packet(packet, now);
    });
    a.replicator->on_error([this, i](const Error& e) {
      const std::string line = "agent" + std::to_string(i) + " rejected: " + e.to_string();
      if (result_.first_rejection.empty()) result_.first_rejection = "t=" + std::to_string(net_.now()) + "ns " + line;
      note(line);
    });
    a.replicator->start(net_.now());
    if (rooms_grammar_)
      a.guard = std::make_unique<agents::GrammarGuard>(
          *a.graph, agents::GrammarChecker(*rooms_grammar_), opt.name);
    if (cfg_.locks.enabled) {
      agents::LockOptions lo;
      lo.lease_ns = cfg_.locks.lease_ns;
      a.locks = std::make_unique<agents::LockManager>(
          *a.graph, a.replicator.get(), [this] { return net_.now(); }, lo);
      a.locks->on_event([this](const agents::LockEvent& e) {
        if (e.kind == agents::LockEventKind::kAcquired) {
          ++result_.lock_acquired;
          result_.lock_acquire_latency_ns.push_back(e.latency_ns);
        }
        if (e.kind == agents::LockEventKind::kLost) ++result_.lock_lost;
        if (e.kind == agents::LockEventKind::kExpired) ++result_.lock_expired;
      });
    }
    install_validators(a);
  }

  // The graph has one commit validator: the grammar check, or the lock check chained after it.
  static void install_validators(Agent& a) {
    if (a.locks)
      a.locks->install(a.guard ? a.guard->validator() : graph::Graph::CommitValidator{});
    else if (a.guard)
      a.guard->install();
  }

  // Scope roots, each with two RT children, created by agent 0 before the workload starts.
  void create_scopes() {
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

  void create_rooms() {
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
    install_validators(agents_[0]);
  }

  // One changeRoom attempt by agent `who`, checked by its grammar.
  void rooms_step(int who) {
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
  void lock_step(int who) {
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

  // Time two agents both hold one scope, split by whether they can hear each other.
  void account_overlap() {
    if (!cfg_.locks.enabled) return;
    bool connected = false, partitioned = false;
    for (std::size_t s = 0; s < scope_roots_.size() && !connected; ++s) {
      const graph::NodeId root = scope_roots_[s];
      std::vector<int> holders;
      for (int i = 0; i < cfg_.agents; ++i) {
        Agent& a = agents_[i];
        if (!a.up) continue;
        if (a.graph->has_node(root) && a.locks->holds(root)) holders.push_back(i);
      }
      for (std::size_t x = 0; x < holders.size(); ++x)
        for (std::size_t y = x + 1; y < holders.size(); ++y) {
          Agent& a = agents_[holders[x]];
          Agent& b = agents_[holders[y]];
          bool hear = net_.group(holders[x]) == net_.group(holders[y]) && a.replicator->peer_alive(b.graph->replica()) &&
                      b.replicator->peer_alive(a.graph->replica());
          (hear ? connected : partitioned) = true;
        }
    }
    if (overlap_since_connected_ >= 0) result_.lock_overlap_connected_ns += net_.now() - overlap_since_connected_;
    if (overlap_since_partitioned_ >= 0) result_.lock_overlap_partitioned_ns += net_.now() - overlap_since_partitioned_;
    overlap_since_connected_ = connected ? net_.now() : -1;
    overlap_since_partitioned_ = partitioned ? net_.now() : -1;
    if (connected && result_.first_violation.empty())
      result_.first_violation = "t=" + std::to_string(net_.now()) + "ns: two connected agents both hold a scope";
  }

  void crash(int i) {
    Agent& a = agents_[i];
    if (!a.up) return;
    // The process dies: its memory (graph, buffers) is gone, nothing is said to anyone.
    a.up = false;
    net_.set_up(i, false);
    add_stats(a);
    a.guard.reset();
    a.locks.reset();
    a.replicator.reset();
    a.graph.reset();
    ++result_.crashes;
    note("agent" + std::to_string(i) + " crashes (kill -9: its replica is lost)");
  }

  void plan_faults(std::int64_t work_end) {
    if (cfg_.faults.partitions && cfg_.agents >= 2) {
      int episodes = 1 + static_cast<int>(rng_.below(3));
      std::vector<std::int64_t> starts;
      for (int e = 0; e < episodes; ++e) starts.push_back(static_cast<std::int64_t>(rng_.below(work_end)));
      std::sort(starts.begin(), starts.end());
      for (int e = 0; e < episodes; ++e) {
        std::int64_t next = e + 1 < episodes ? starts[e + 1] : work_end;
        std::int64_t len = 50'000'000 + static_cast<std::int64_t>(rng_.below(1'500'000'000));
        std::int64_t end = std::min(starts[e] + len, next);
        int ngroups = 2 + static_cast<int>(rng_.below(std::min(cfg_.agents - 1, 3)));
        std::vector<int> groups(cfg_.agents);
        for (int i = 0; i < cfg_.agents; ++i) groups[i] = i < ngroups ? i : static_cast<int>(rng_.below(ngroups));
        rng_.shuffle(groups);
        net_.at(starts[e], [this, groups] { partition(groups); });
        net_.at(end, [this] {
          net_.heal();
          note("partition healed");
        });
      }
    }
    if (cfg_.faults.crashes) {
      int n = 1 + static_cast<int>(rng_.below(std::max(1, cfg_.agents / 3)));
      for (int k = 0; k < n; ++k) {
        int who = static_cast<int>(rng_.below(cfg_.agents));
        std::int64_t at = static_cast<std::int64_t>(rng_.below(work_end));
        std::int64_t back = at + 20'000'000 + static_cast<std::int64_t>(rng_.below(1'500'000'000));
        net_.at(at, [this, who] { crash(who); });
        if (back < work_end)
          net_.at(back, [this, who] {
            if (!agents_[who].up) boot(who);
          });
      }
    }
  }

  void tick(int i) {
    if (agents_[i].up) {
      agents_[i].replicator->tick(net_.now());
      if (agents_[i].locks) agents_[i].locks->tick();
      if (agents_[i].guard) agents_[i].guard->tick();
    }
    net_.at(net_.now() + cfg_.tick_interval_ns, [this, i] { tick(i); });
  }

  void partition(const std::vector<int>& groups) {
    ++result_.partitions;
    std::string split;
    for (int i = 0; i < cfg_.agents; ++i) {
      net_.set_group(i, groups[i]);
      split += (i ? " " : "") + std::to_string(groups[i]);
    }
    note("partition: groups by agent [" + split + "]");
  }

  void step() {
    ++steps_done_;
    if (cfg_.progress) cfg_.progress(steps_done_, cfg_.steps);
    std::vector<int> up;
    for (int i = 0; i < cfg_.agents; ++i)
      if (agents_[i].up) up.push_back(i);
    if (up.empty()) return;
    int who = rng_.pick(up);
    if (cfg_.rooms.enabled) rooms_step(who);
    else if (cfg_.locks.enabled && rng_.chance(0.5)) lock_step(who);
    else result_.ops += churn_.step(*agents_[who].graph, rng_, net_.now());
    if (cfg_.check_every_step) check_invariants_all();
  }

  // Adds an agent's counters to the result (when it crashes, and for every agent at the end).
  void add_stats(const Agent& a) {
    const agents::ReplicatorStats& st = a.replicator->stats();
    result_.deltas_applied += st.deltas_applied;
    result_.states_applied += st.states_applied;
    result_.rejected_packets += st.rejected_packets;
    if (a.guard) {
      result_.violations_seen += a.guard->violations_seen();
      result_.repairs += a.guard->repairs_made();
    }
  }

  void check_invariants_all() {
    for (auto& a : agents_) {
      if (!a.up) continue;
      auto v = a.graph->check_invariants();
      if (!v.empty() && result_.first_violation.empty())
        result_.first_violation = "t=" + std::to_string(net_.now()) + "ns agent " + a.graph->replica().to_string() + ": " + v[0];
      result_.invariant_violations += v.size();
    }
  }

  bool converged() {
    const Agent& first = agents_[0];
    Digest128 d = first.graph->digest();
    for (const auto& a : agents_) {
      if (!a.up) return false;
      if (!(a.replicator->applied() == first.replicator->applied())) return false;
      if (!(a.graph->digest() == d)) return false;
    }
    // With a repairing agent, quiescence also means the repairs are done.
    if (cfg_.rooms.enabled && cfg_.rooms.repair && !first.guard->checker().all_violations(*first.graph).empty())
      return false;
    return true;
  }

  SimConfig cfg_;
  int steps_done_ = 0;
  Rng rng_;
  VirtualNetwork net_;
  std::vector<Agent> agents_;
  std::optional<agents::Grammar> rooms_grammar_;  // parsed once, copied into every agent's guard
  std::vector<graph::NodeId> scope_roots_;        // "scope0", ... as create_scopes made them
  Churn churn_{ChurnMix{}};
  SimResult result_;
  std::int64_t overlap_since_connected_ = -1;
  std::int64_t overlap_since_partitioned_ = -1;
};

}  // namespace

agents::ReplicatorOptions SimConfig::default_replicator() {
  agents::ReplicatorOptions o;
  o.heartbeat_ns = 50'000'000;
  o.lease_ns = 400'000'000;
  o.pull_timeout_ns = 200'000'000;
  o.pull_first_timeout_ns = 50'000'000;
  o.gap_grace_ns = 40'000'000;
  o.buffer_bytes = 24u << 10;
  o.chunk_bytes = 2u << 10;
  return o;
}

std::string SimResult::to_json() const {
  nlohmann::json j;
  j["seed"] = seed;
  j["agents"] = agents;
  j["steps"] = steps;
  j["converged"] = converged;
  j["invariant_violations"] = invariant_violations;
  if (!first_violation.empty()) j["first_violation"] = first_violation;
  if (!first_rejection.empty()) j["first_rejection"] = first_rejection;
  j["digest"] = digest;
  j["messages"] = messages;
  j["bytes"] = bytes;
  j["dropped"] = dropped;
  j["duplicated"] = duplicated;
  j["ops"] = ops;
  j["crashes"] = crashes;
  j["partitions"] = partitions;
  j["deltas_applied"] = deltas_applied;
  j["states_applied"] = states_applied;
  j["rejected_packets"] = rejected_packets;
  j["final_nodes"] = final_nodes;
  j["final_edges"] = final_edges;
  if (moves + moves_refused > 0) {
    j["moves"] = moves;
    j["moves_refused"] = moves_refused;
    j["violations_seen"] = violations_seen;
    j["repairs"] = repairs;
    j["final_violations"] = final_violations;
  }
  if (lock_acquired + lock_lost + lock_expired + lock_refused > 0) {
    j["lock_acquired"] = lock_acquired;
    j["lock_lost"] = lock_lost;
    j["lock_expired"] = lock_expired;
    j["lock_refused"] = lock_refused;
    j["lock_overlap_connected_ms"] = lock_overlap_connected_ns / 1e6;
    j["lock_overlap_partitioned_ms"] = lock_overlap_partitioned_ns / 1e6;
  }
  j["virtual_ms"] = virtual_ms;
  j["settle_ms"] = settle_ms;
  return j.dump();
}

SimResult run_simulation(const SimConfig& config) { return Simulation(config).run(); }

SimConfig mixed_config(std::uint64_t seed, int steps) {
  Rng r(seed ^ 0x6d69786564ULL);
  SimConfig c;
  c.seed = seed;
  c.steps = steps;
  c.agents = 3 + static_cast<int>(r.below(14));
  const double losses[] = {0.0, 0.05, 0.2, 0.5};
  c.faults.loss = losses[r.below(4)];
  c.faults.dup = r.chance(0.5) ? 0.1 : 0.0;
  c.faults.reorder = r.chance(0.5);
  c.faults.partitions = r.chance(0.5);
  c.faults.crashes = r.chance(0.5);
  return c;
}

}  // namespace quiver::sim
