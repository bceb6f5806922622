#include "quiver/sim/simulator.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <queue>

#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/base/hash.h"
#include "quiver/base/rng.h"

namespace quiver::sim {
namespace {

using agents::PeerId;

class Simulation;

// A simulated disk under an agent's store: faults are decided here, in virtual time.
struct Disk {
  std::string dir;
  Rng rng{1};
  std::int64_t full_from = -1, full_until = -1;  // the disk refuses writes in [from, until)
  bool power_off = false;  // the host lost power: nothing more reaches the disk
  bool tear_next = false;  // the next log write tears, and the power fails during it
  bool torn = false;       // a write tore: the host must go down now
  bool lying = false;      // control: log writes are acknowledged and dropped
};

struct Agent {
  std::uint64_t agent_id = 0;
  std::uint64_t incarnation = 0;
  std::uint64_t last_incarnation = 0;  // the greatest incarnation ever used (fresh ones go beyond)
  bool up = false;
  bool failing = false;  // fail-stopped: down for the network, to be killed at once
  Disk disk;
  crdt::CausalContext acked;  // this agent's acknowledged commits, every incarnation
  std::unique_ptr<agents::Store> store;  // declared before the replicator: destroyed after it
  std::unique_ptr<graph::Graph> graph;
  std::unique_ptr<agents::Replicator> replicator;
  /// Runs the replica (the same engine as an agent's, with no agent): its timers, locks, guard.
  std::unique_ptr<agents::Engine> engine;
  agents::LockManager* locks = nullptr;   // the engine's (lock workload)
  agents::GrammarGuard* guard = nullptr;  // the engine's (rooms workload)
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
    agents_.resize(cfg.agents);
    net_.after_each_event([this] { account_overlap(); });
    boot_pending_.assign(cfg.agents, false);
    if (cfg.disks.enabled) make_disks();
  }

  ~Simulation() {
    for (auto& a : agents_) {
      a.engine.reset();
      a.replicator.reset();
      a.store.reset();
    }
    if (own_dir_) {
      std::error_code ec;
      std::filesystem::remove_all(root_, ec);
    }
  }

  SimResult run() {
    for (int i = 0; i < cfg_.agents; ++i) {
      // A store names its replica's local changes by the agent's name, as a process does.
      agents_[i].agent_id = cfg_.disks.enabled ? fnv1a64("agent" + std::to_string(i)) : 0x5100 + static_cast<std::uint64_t>(i);
      boot(i);
      net_.at(static_cast<std::int64_t>(rng_.below(cfg_.tick_interval_ns)), [this, i] { tick(i); });
    }
    const std::int64_t work_end = cfg_.steps * cfg_.step_interval_ns;
    if (cfg_.locks.enabled) create_scopes();
    if (cfg_.rooms.enabled) create_rooms();
    for (int s = 0; s < cfg_.steps; ++s) net_.at((s + 1) * cfg_.step_interval_ns, [this] { step(); });
    plan_faults(work_end);
    if (cfg_.disks.enabled) plan_disk_faults(work_end);
    // Workload and faults.
    net_.run_until(work_end + cfg_.step_interval_ns);
    // Heal: faults off, everyone up and connected; then wait for convergence.
    note("workload done (" + std::to_string(result_.ops) + " changes); faults off, partitions healed, crashed agents restart");
    net_.faults().loss = 0;
    net_.faults().dup = 0;
    net_.heal();
    for (auto& a : agents_) {
      a.disk.full_until = std::min(a.disk.full_until, net_.now());
      a.disk.tear_next = false;
    }
    for (int i = 0; i < cfg_.agents; ++i)
      if (!agents_[i].up) boot(i);
    const std::int64_t heal_at = net_.now();
    settle(net_.now() + cfg_.settle_limit_ns);
    if (cfg_.disks.enabled && result_.converged) {
      // Every agent loses power at once and comes back from its store alone: under `always`
      // what they reload must hold every acknowledged commit; then they converge again.
      note("every agent loses power at once; all restart from their stores");
      for (int i = 0; i < cfg_.agents; ++i) crash(i);
      for (int i = 0; i < cfg_.agents; ++i) boot(i);
      settle(net_.now() + cfg_.settle_limit_ns);
      if (cfg_.disks.durability == agents::Durability::kAlways)
        for (int i = 0; i < cfg_.agents; ++i)
          if (agents_[i].up) check_acked(i, agents_[i].replicator->applied(), "the final replicas");
    }
    account_overlap();
    result_.settle_ms = (net_.now() - heal_at) / 1'000'000;
    result_.virtual_ms = net_.now() / 1'000'000;
    result_.messages = net_.stats().messages;
    result_.bytes = net_.stats().bytes;
    result_.dropped = net_.stats().dropped;
    result_.retransmitted = net_.stats().retransmitted;
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

  void settle(std::int64_t deadline) {
    result_.converged = false;
    while (net_.now() < deadline) {
      net_.run_until(net_.now() + 50'000'000);
      if (cfg_.disks.enabled)
        for (int i = 0; i < cfg_.agents; ++i)
          if (!agents_[i].up && !boot_pending_[i]) boot(i);  // a restart the disk refused, retried
      if (converged()) {
        result_.converged = true;
        note("converged: " + std::to_string(cfg_.agents) + " replicas hold digest " +
             agents_[0].graph->digest().hex() + " (" + std::to_string(agents_[0].graph->node_count()) + " nodes)");
        break;
      }
    }
  }

  // ---------------------------------------------------------------- stores on simulated disks

  void make_disks() {
    if (cfg_.disks.dir.empty()) {
      // In memory when we can: the disks are simulated, the host's fdatasync would only cost time.
      std::error_code ec;
      const std::filesystem::path base =
          std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm") : std::filesystem::temp_directory_path();
      std::string tmpl = (base / "quiver-sim-disks-XXXXXX").string();
      if (::mkdtemp(tmpl.data()) == nullptr) {
        store_error("cannot create a temporary directory for the stores");
        return;
      }
      root_ = tmpl;
      own_dir_ = true;
    } else {
      root_ = cfg_.disks.dir;
    }
    for (int i = 0; i < cfg_.agents; ++i) {
      Disk& d = agents_[i].disk;
      d.dir = (std::filesystem::path(root_) / ("agent" + std::to_string(i))).string();
      d.rng = Rng(cfg_.seed ^ (0xd15c0000ULL + static_cast<std::uint64_t>(i)));
      d.lying = cfg_.disks.lying_disk && i == 0;
    }
  }

  void store_error(const std::string& e) {
    if (result_.first_store_error.empty()) result_.first_store_error = "t=" + std::to_string(net_.now()) + "ns " + e;
    note(e);
  }

  // The fault the disk of agent `i` injects into a write. Called on the thread that writes:
  // the owner's (always), or the store's while the owner waits in sync() (batch): in order.
  agents::StoreFault disk_fault(int i, const agents::StoreWrite& w) {
    using Kind = agents::StoreFault::Kind;
    Disk& d = agents_[i].disk;
    if (d.power_off) return {Kind::kNoSpace};
    const bool log = w.what == agents::StoreWrite::What::kLog;
    if (log && d.tear_next) {
      d.tear_next = false;
      d.torn = true;
      d.power_off = true;
      ++result_.torn_writes;
      agents::StoreFault f{Kind::kTear};
      f.flip = d.rng.chance(0.3);
      f.keep = static_cast<std::size_t>(d.rng.below(std::max<std::size_t>(1, w.bytes)));
      return f;
    }
    if (net_.now() >= d.full_from && net_.now() < d.full_until) {
      ++result_.writes_refused;
      return {Kind::kNoSpace};
    }
    if (log && d.lying) return {Kind::kLie};
    return {};
  }

  // Under `always` a write failed: the host stops at once (nothing leaves it from now on).
  void fail_stop(int i, const Error& e) {
    Agent& a = agents_[i];
    if (a.failing) return;
    a.failing = true;
    ++result_.fail_stops;
    net_.set_up(i, false);
    note("agent" + std::to_string(i) + " stops (fail-stop): " + e.message);
    net_.at(net_.now(), [this, i] {
      crash(i);
      restart_later(i, 20'000'000);
    });
  }

  void restart_later(int i, std::int64_t after_ns) {
    boot_pending_[i] = true;
    net_.at(net_.now() + after_ns, [this, i] {
      boot_pending_[i] = false;
      if (!agents_[i].up) boot(i);
    });
  }

  // Opens agent i's store and loads its replica into a new graph. False: the disk refused (the
  // caller retries later).
  bool open_store(int i, crdt::CausalContext& applied) {
    Agent& a = agents_[i];
    agents::StoreOptions so;
    so.dir = a.disk.dir;
    so.durability = cfg_.disks.durability;
    so.batch_ns = 0;            // flushed by the simulator, in virtual time
    so.compact_log_bytes = 0;   // compacted by the simulator, in virtual time
    so.map_bytes = std::size_t{1} << 30;
    so.faults.before_write = [this, i](const agents::StoreWrite& w) { return disk_fault(i, w); };
    so.faults.fail_stop = [this, i](const Error& e) { fail_stop(i, e); };
    const std::string name = "agent" + std::to_string(i);
    for (int attempt = 0; attempt < 2; ++attempt) {
      const std::uint64_t fresh = a.last_incarnation + 1;
      auto s = agents::Store::open(so, name, fresh);
      Error err;
      if (s.ok()) {
        a.store = std::move(*s);
        a.incarnation = a.store->opening().incarnation;
        a.last_incarnation = std::max(a.last_incarnation, a.incarnation);
        a.graph = std::make_unique<graph::Graph>(graph::ReplicaId{a.agent_id, a.incarnation});
        auto loaded = a.store->load(*a.graph);
        if (loaded.ok()) {
          applied = std::move(*loaded);
          ++result_.store_reloads;
          result_.records_reloaded += a.store->opening().records;
          if (!a.store->opening().torn_tail.empty()) {
            ++result_.torn_tails_dropped;
            note(name + ": " + a.store->opening().torn_tail);
          }
          return true;
        }
        err = loaded.error();
        a.store.reset();
        a.graph.reset();
      } else {
        err = s.error();
      }
      if (err.code != ErrorCode::kMalformed && err.code != ErrorCode::kTruncated &&
          err.code != ErrorCode::kUnsupportedVersion) {
        ++result_.restarts_refused;
        note(name + " cannot open its store, retries: " + err.to_string());
        return false;
      }
      // Damage: as DdsReplica does, set the store aside and start empty, filled by the peers.
      ++result_.stores_set_aside;
      store_error(name + ": " + err.to_string() + "; the store is set aside");
      if (auto aside = agents::Store::set_aside(a.disk.dir); !aside.ok()) {
        store_error(aside.error().to_string());
        return false;
      }
    }
    return false;
  }

  // Under `always`: every commit agent i acknowledged must be in `have`.
  void check_acked(int i, const crdt::CausalContext& have, const std::string& where) {
    std::uint64_t lost = 0;
    std::string first;
    agents_[i].acked.for_each_range([&](const graph::ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
      for (std::uint64_t c = lo; c <= hi; ++c)
        if (!have.contains(r, c)) {
          if (first.empty()) first = r.to_string() + ":" + std::to_string(c);
          ++lost;
        }
    });
    if (lost == 0) return;
    result_.acked_lost += lost;
    const std::string line = "agent" + std::to_string(i) + ": " + std::to_string(lost) +
                             " acknowledged commits missing from " + where + " (first " + first + ")";
    if (result_.first_acked_lost.empty()) result_.first_acked_lost = "t=" + std::to_string(net_.now()) + "ns " + line;
    note(line);
  }

  void plan_disk_faults(std::int64_t work_end) {
    const DiskFaults& d = cfg_.disks;
    // Flushes (batch) and compactions, each store on its own phase.
    for (int i = 0; i < cfg_.agents; ++i) {
      if (d.durability != agents::Durability::kAlways)
        every(static_cast<std::int64_t>(rng_.below(d.flush_ns)) + 1, d.flush_ns, [this, i] { flush(i); });
      every(static_cast<std::int64_t>(rng_.below(d.compact_ns)) + 1, d.compact_ns, [this, i] { compact(i); });
    }
    if (d.disk_full) {
      const int episodes = 1 + static_cast<int>(rng_.below(3));
      for (int e = 0; e < episodes; ++e) {
        const int who = static_cast<int>(rng_.below(cfg_.agents));
        const std::int64_t from = static_cast<std::int64_t>(rng_.below(work_end));
        const std::int64_t len = 30'000'000 + static_cast<std::int64_t>(rng_.below(600'000'000));
        net_.at(from, [this, who, len] {
          Disk& k = agents_[who].disk;
          k.full_from = net_.now();
          k.full_until = net_.now() + len;
          note("agent" + std::to_string(who) + "'s disk is full for " + std::to_string(len / 1'000'000) + " ms");
        });
        // Under batch the agent goes on without its store; a later power cut brings it back.
        if (d.durability != agents::Durability::kAlways && rng_.chance(0.5)) {
          const std::int64_t cut = from + len + static_cast<std::int64_t>(rng_.below(300'000'000));
          net_.at(cut, [this, who] { power_cut(who, 20'000'000); });
        }
      }
    }
    if (d.power_cut_all) {
      const std::int64_t at = static_cast<std::int64_t>(rng_.below(work_end));
      const std::int64_t back = 20'000'000 + static_cast<std::int64_t>(rng_.below(500'000'000));
      net_.at(at, [this, back] {
        note("every agent loses power at once");
        for (int i = 0; i < cfg_.agents; ++i) power_cut(i, back);
      });
    }
  }

  void every(std::int64_t first, std::int64_t period, std::function<void()> fn) {
    net_.at(net_.now() + first, [this, period, fn] {
      fn();
      every(period, period, fn);
    });
  }

  void flush(int i) {
    Agent& a = agents_[i];
    if (!a.up || a.failing || !a.store) return;
    (void)a.store->sync();
    after_write(i);
  }

  void compact(int i) {
    Agent& a = agents_[i];
    if (!a.up || a.failing || !a.store) return;
    const std::uint64_t before = a.store->stats().compactions;
    if (Status s = a.store->compact(); !s.ok()) {
      ++result_.compactions_failed;
      note("agent" + std::to_string(i) + ": store: " + s.error().message);
    }
    result_.compactions += a.store->stats().compactions - before;
    after_write(i);
  }

  // A write tore (the power failed during it): the host goes down now.
  void after_write(int i) {
    if (agents_[i].disk.torn && agents_[i].up) power_cut(i, 20'000'000);
  }

  // The host of agent i loses power: the process dies with what its store had not written.
  void power_cut(int i, std::int64_t back_after_ns) {
    if (!agents_[i].up) return;
    ++result_.power_cuts;
    crash(i);
    restart_later(i, back_after_ns);
  }

  void boot(int i) {
    Agent& a = agents_[i];
    crdt::CausalContext applied;
    if (cfg_.disks.enabled) {
      a.disk.power_off = false;
      a.disk.torn = false;
      if (!open_store(i, applied)) {
        restart_later(i, 100'000'000);
        return;
      }
      note("agent" + std::to_string(i) + (a.store->opening().created ? " starts with a new store" : " restarts from its store") +
           " as incarnation " + std::to_string(a.incarnation) + (a.store->opening().incarnation_kept ? " (kept)" : "") +
           " (" + std::to_string(a.store->opening().records) + " records)");
      if (cfg_.disks.durability == agents::Durability::kAlways) check_acked(i, applied, "its store");
    } else {
      if (a.incarnation > 0) note("agent" + std::to_string(i) + " restarts as incarnation " + std::to_string(a.incarnation + 1) + " with an empty replica");
      ++a.incarnation;
      a.graph = std::make_unique<graph::Graph>(graph::ReplicaId{a.agent_id, a.incarnation});
    }
    a.up = true;
    a.failing = false;
    net_.set_up(i, true);
    net_.set_address(i, a.graph->replica());
    agents::ReplicatorOptions opt = cfg_.replicator;
    opt.name = "agent" + std::to_string(i);
    a.replicator = std::make_unique<agents::Replicator>(*a.graph, net_.endpoint(i), opt);
    net_.set_receiver(i, [this, i](const agents::CdrSample& sample, std::int64_t) {
      Agent& t = agents_[i];
      auto decoded = agents::decode_cdr_sample(sample.topic, sample.bytes);
      if (decoded.ok()) t.engine->on_sample(*decoded);
      else t.replicator->on_undecodable(decoded.error());
    });
    a.replicator->on_error([this, i](const Error& e) {
      const std::string line = "agent" + std::to_string(i) + " rejected: " + e.to_string();
      if (result_.first_rejection.empty()) result_.first_rejection = "t=" + std::to_string(net_.now()) + "ns " + line;
      note(line);
    });
    if (a.store) {
      a.replicator->restore(applied);
      a.replicator->set_journal(a.store.get());
    }
    a.replicator->start(net_.now());
    agents::EngineOptions eo;
    eo.clock = [this] { return net_.now(); };
    eo.jobs = agents::JobRunner::Mode::kInline;
    eo.locks_enabled = cfg_.locks.enabled;
    eo.locks.lease_ns = cfg_.locks.lease_ns;
    if (cfg_.rooms.enabled) {
      eo.grammar_text = rooms_grammar(cfg_.rooms.repair);
      eo.grammar_source = "rooms";
    }
    a.engine = std::make_unique<agents::Engine>(*a.graph, a.replicator.get(), std::move(eo));
    a.locks = a.engine->lock_manager();
    if (a.locks)
      a.locks->on_event([this](const agents::LockEvent& e) {
        if (e.kind == agents::LockEventKind::kAcquired) {
          ++result_.lock_acquired;
          result_.lock_acquire_latency_ns.push_back(e.latency_ns);
        }
        if (e.kind == agents::LockEventKind::kLost) ++result_.lock_lost;
        if (e.kind == agents::LockEventKind::kExpired) ++result_.lock_expired;
      });
    // The grammar and lock checks go on the graph.
    if (Status st = a.engine->start(); !st.ok()) note("agent" + std::to_string(i) + ": " + st.error().to_string());
    a.guard = a.engine->guard();
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
    agents_[0].engine->install_checks();
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
    a.engine.reset();
    a.locks = nullptr;
    a.guard = nullptr;
    a.replicator.reset();
    if (a.store) {
      // The power is off: what the store had not written is lost (its last sync() fails).
      a.disk.power_off = true;
      a.store.reset();
      a.disk.power_off = false;
    }
    a.graph.reset();
    a.failing = false;
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
        if (cfg_.disks.enabled && cfg_.disks.torn_writes && rng_.chance(0.5)) {
          // The power fails during the next write of its store (the host goes down then).
          net_.at(at, [this, who] {
            if (agents_[who].up) agents_[who].disk.tear_next = true;
          });
          continue;
        }
        net_.at(at, [this, who] { crash(who); });
        if (back < work_end)
          net_.at(back, [this, who] {
            if (!agents_[who].up) boot(who);
          });
      }
    }
  }

  void tick(int i) {
    if (agents_[i].up && !agents_[i].failing) {
      agents_[i].engine->step();
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
      if (agents_[i].up && !agents_[i].failing) up.push_back(i);
    if (up.empty()) return;
    int who = rng_.pick(up);
    if (cfg_.rooms.enabled) rooms_step(who);
    else if (cfg_.locks.enabled && rng_.chance(0.5)) lock_step(who);
    else {
      Agent& a = agents_[who];
      const std::uint64_t before = a.replicator->applied().max_counter(a.graph->replica());
      result_.ops += churn_.step(*a.graph, rng_, net_.now());
      // The commit returned with the host up: acknowledged. (One whose write failed stopped
      // the host first: never acknowledged.)
      if (cfg_.disks.enabled && a.up && !a.failing) {
        const std::uint64_t after = a.replicator->applied().max_counter(a.graph->replica());
        if (after > before) {
          a.acked.add_range(a.graph->replica(), before + 1, after);
          result_.acked += after - before;
        }
      }
    }
    if (cfg_.check_every_step) check_invariants_all();
  }

  // Adds an agent's counters to the result (when it crashes, and for every agent at the end).
  void add_stats(const Agent& a) {
    const agents::ReplicatorStats& st = a.replicator->stats();
    result_.deltas_applied += st.deltas_applied;
    result_.states_applied += st.states_applied;
    result_.rejected_samples += st.rejected;
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
  std::string root_;       // the stores' directory
  bool own_dir_ = false;   // made by us: removed at the end
  std::vector<bool> boot_pending_;  // a restart is scheduled
  int steps_done_ = 0;
  Rng rng_;
  VirtualNetwork net_;
  std::vector<Agent> agents_;
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
  j["retransmitted"] = retransmitted;
  j["duplicated"] = duplicated;
  j["ops"] = ops;
  j["crashes"] = crashes;
  j["partitions"] = partitions;
  j["deltas_applied"] = deltas_applied;
  j["states_applied"] = states_applied;
  j["rejected_samples"] = rejected_samples;
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
  if (power_cuts + fail_stops + store_reloads > 0) {
    j["acked"] = acked;
    j["acked_lost"] = acked_lost;
    if (!first_acked_lost.empty()) j["first_acked_lost"] = first_acked_lost;
    j["power_cuts"] = power_cuts;
    j["torn_writes"] = torn_writes;
    j["torn_tails_dropped"] = torn_tails_dropped;
    j["writes_refused"] = writes_refused;
    j["fail_stops"] = fail_stops;
    j["store_reloads"] = store_reloads;
    j["records_reloaded"] = records_reloaded;
    j["restarts_refused"] = restarts_refused;
    j["stores_set_aside"] = stores_set_aside;
    j["compactions"] = compactions;
    j["compactions_failed"] = compactions_failed;
    if (!first_store_error.empty()) j["first_store_error"] = first_store_error;
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
