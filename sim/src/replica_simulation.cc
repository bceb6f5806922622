// The replica simulator's run and its phases: boot of a replica (from its store, or empty), the
// workload steps, crash, the heal after the workload and the wait for convergence (settle).
#include <algorithm>
#include <filesystem>
#include <memory>

#include "quiver/base/hash.h"
#include "replica_simulation.h"

namespace quiver::sim {

Simulation::Simulation(const SimConfig& cfg)
    : cfg_(cfg), rng_(cfg.seed), net_(cfg.agents + 2 * robots(cfg), rng_.fork(), cfg.faults) {
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
  if (robots() > 0) make_team();
}

Simulation::~Simulation() {
  for (auto& g : gateways_) g.bridge.reset();
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

SimResult Simulation::run() {
  for (int i = 0; i < cfg_.agents; ++i) {
    // A store names its replica's local changes by the agent's name, as a process does.
    agents_[i].agent_id = cfg_.disks.enabled ? fnv1a64("agent" + std::to_string(i)) : 0x5100 + static_cast<std::uint64_t>(i);
    boot(i);
    net_.at(static_cast<std::int64_t>(rng_.below(cfg_.tick_interval_ns)), [this, i] { tick(i); });
  }
  const std::int64_t work_end = cfg_.steps * cfg_.step_interval_ns;
  for (int r = 0; r < robots(); ++r) {
    boot_gateway(r);
    net_.at(static_cast<std::int64_t>(rng_.below(cfg_.tick_interval_ns)), [this, r] { tick_gateway(r); });
  }
  if (cfg_.locks.enabled) create_scopes();
  if (cfg_.rooms.enabled) create_rooms();
  for (int s = 0; s < cfg_.steps; ++s) net_.at((s + 1) * cfg_.step_interval_ns, [this] { step(); });
  plan_faults(work_end);
  if (cfg_.split_until_end && cfg_.agents >= 2)
    net_.at(work_end / 5, [this] {
      note("split into two halves (even and odd agents) until the workload ends");
      ++result_.partitions;
      for (int i = 0; i < cfg_.agents; ++i) net_.set_group(i, i % 2);
    });
  if (cfg_.disks.enabled) plan_disk_faults(work_end);
  // Workload and faults.
  net_.run_until(work_end + cfg_.step_interval_ns);
  // Heal: faults off, everyone up and connected; then wait for convergence.
  note("workload done (" + std::to_string(result_.ops) + " changes); faults off, partitions healed, crashed agents restart");
  net_.faults().loss = 0;
  net_.faults().dup = 0;
  net_.heal();
  if (robots() > 0) team_heal();
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
  result_.settle_ms = (net_.now() - heal_at) / 1'000'000;
  if (robots() > 0 && result_.converged) check_team_members();
  account_overlap();
  result_.virtual_ms = net_.now() / 1'000'000;
  result_.messages = net_.stats().messages;
  result_.bytes = net_.stats().bytes;
  result_.robots = robots();
  if (robots() > 0 && net_.stats().segment_bytes.size() > static_cast<std::size_t>(robots()))
    result_.team_bytes = net_.stats().segment_bytes[robots()];
  result_.dropped = net_.stats().dropped;
  result_.introductions = net_.stats().introductions;
  result_.retransmitted = net_.stats().retransmitted;
  result_.duplicated = net_.stats().duplicated;
  for (std::size_t k = 0; k < agents::kDdsTopicCount; ++k) {
    static constexpr const char* kKinds[] = {"summary", "delta", "pull", "state", "bye"};
    result_.by_kind[kKinds[k]] = {net_.stats().topic_messages[k], net_.stats().topic_bytes[k]};
  }
  {
    std::size_t total = 0, n = 0;
    for (const auto& a : agents_)
      if (a.up && a.replicator) {
        const std::size_t b = a.replicator->protocol_bytes();
        result_.protocol_bytes_max = std::max(result_.protocol_bytes_max, b);
        total += b;
        ++n;
      }
    result_.protocol_bytes_mean = n ? total / n : 0;
  }
  if (cfg_.idle_ns > 0) {
    note("idle for " + std::to_string(cfg_.idle_ns / 1'000'000) + " ms");
    net_.run_until(net_.now() + cfg_.idle_ns);
    result_.idle_messages = net_.stats().messages - result_.messages;
    result_.idle_bytes = net_.stats().bytes - result_.bytes;
  }
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

void Simulation::note(const std::string& line) {
  if (cfg_.log) cfg_.log(net_.now(), line);
}

void Simulation::settle(std::int64_t deadline) {
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

void Simulation::boot(int i) {
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
  // The network introduces peers as DDS discovery does (a hello then needs only a few answers).
  a.replicator = std::make_unique<agents::Replicator>(*a.graph, net_.endpoint(i), opt);
  net_.discover(i, {a.graph->replica(), opt.name, opt.observer}, [this, i](const agents::PeerCard& c) {
    if (agents_[i].replicator) agents_[i].replicator->introduce(c);
  });
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

void Simulation::crash(int i) {
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

void Simulation::tick(int i) {
  if (agents_[i].up && !agents_[i].failing) {
    agents_[i].engine->step();
  }
  net_.at(net_.now() + cfg_.tick_interval_ns, [this, i] { tick(i); });
}

void Simulation::step() {
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
void Simulation::add_stats(const Agent& a) {
  const agents::ReplicatorStats& st = a.replicator->stats();
  result_.deltas_applied += st.deltas_applied;
  result_.states_applied += st.states_applied;
  result_.rejected_samples += st.rejected;
  result_.pulls += st.pulls_sent;
  result_.suspicions += st.suspicions;
  result_.refutations += st.refutations;
  result_.declared_gone += st.declared_gone;
  if (a.guard) {
    result_.violations_seen += a.guard->violations_seen();
    result_.repairs += a.guard->repairs_made();
  }
}

}  // namespace quiver::sim
