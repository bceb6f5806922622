#pragma once
// The replica simulator of `quiver sim` (simulator.h), private to sim/: one Simulation, its bare
// replicas (each on the agent engine, with no agent) on the virtual network, and what it does
// to them, one concern per file:
//   replica_simulation.cc  the run and its phases: boot, workload steps, crash, heal, settle
//   replica_faults.cc      the fault schedule (fault_generator.h), played by name (FaultTarget)
//   replica_disks.cc       durable stores on simulated disks: power cuts, full disks, torn
//                          writes, acknowledged-commit checks
//   replica_workloads.cc   the lock and rooms workloads
//   replica_checks.cc      invariants, lock overlap, convergence
//   replica_team.cc        robot teams: robots as networks joined by gateways (TeamSim)
//   simulator.cc           run_simulation(), SimResult's JSON, SimConfig's defaults
//
// Threading: the simulator's one thread (a store's writer calls in while the owner waits).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "quiver/agents/replica/replication/bridge.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/base/rng.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/network.h"
#include "quiver/sim/simulator.h"
#include "quiver/sim/workload.h"
#include "sim_gateway.h"

namespace quiver::sim {

class Simulation final : public FaultTarget {
 public:
  explicit Simulation(const SimConfig& cfg);
  ~Simulation() override;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  SimResult run();

  // FaultTarget: the agents are "agent0".."agentN-1" (replica_faults.cc).
  std::int64_t now() const override { return net_.now(); }
  void at(std::int64_t t_ns, std::function<void()> fn) override { net_.at(t_ns, std::move(fn)); }
  void partition(const std::vector<std::vector<std::string>>& groups) override;
  void heal() override;
  bool kill(const std::string& agent) override;
  bool restart(const std::string& agent) override;
  void set_loss(double p) override;

 private:
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

  // The run (replica_simulation.cc).
  void note(const std::string& line);
  void settle(std::int64_t deadline);
  void boot(int i);
  void crash(int i);
  void tick(int i);
  void step();
  void add_stats(const Agent& a);

  // Faults (replica_faults.cc).
  static std::string name(int i) { return "agent" + std::to_string(i); }
  int index(const std::string& agent) const;
  void plan_faults(std::int64_t work_end);

  // Stores on simulated disks (replica_disks.cc).
  void make_disks();
  void store_error(const std::string& e);
  agents::StoreFault disk_fault(int i, const agents::StoreWrite& w);
  void fail_stop(int i, const Error& e);
  void restart_later(int i, std::int64_t after_ns);
  bool open_store(int i, crdt::CausalContext& applied);
  void check_acked(int i, const crdt::CausalContext& have, const std::string& where);
  void plan_disk_faults(std::int64_t work_end);
  void every(std::int64_t first, std::int64_t period, std::function<void()> fn);
  void flush(int i);
  void compact(int i);
  void after_write(int i);
  void power_cut(int i, std::int64_t back_after_ns);

  // Workloads (replica_workloads.cc).
  static std::string rooms_grammar(bool repair);
  void create_scopes();
  void create_rooms();
  void rooms_step(int who);
  void lock_step(int who);

  // Robot teams (replica_team.cc): gateway r's replicas are network nodes gateway_node(r, 0) (on
  // robot r's network) and gateway_node(r, 1) (on the team's).
  static int robots(const SimConfig& c) { return c.team.robots >= 2 ? c.team.robots : 0; }
  int robots() const { return robots(cfg_); }
  int robot_of(int agent) const { return agent % robots(); }
  int gateway_node(int r, int side) const { return cfg_.agents + 2 * r + side; }
  void make_team();
  SimGateway::Place gateway_place(int r) const;
  void boot_gateway(int r);
  void crash_gateway(int r);
  void tick_gateway(int r);
  int gateway_index(const std::string& name) const;
  void team_partition(const std::vector<std::vector<std::string>>& groups);
  void team_heal();
  bool gateways_converged(const Digest128& d, const crdt::CausalContext& applied) const;
  void check_team_members();

  // Checks (replica_checks.cc).
  bool linked(int x, int y) const;  // samples can go between two agents now
  void account_overlap();
  void check_invariants_all();
  bool converged();

  SimConfig cfg_;
  std::string root_;       // the stores' directory
  bool own_dir_ = false;   // made by us: removed at the end
  std::vector<bool> boot_pending_;  // a restart is scheduled
  int steps_done_ = 0;
  Rng rng_;
  VirtualNetwork net_;
  std::vector<Agent> agents_;
  std::vector<SimGateway> gateways_;
  std::vector<graph::NodeId> scope_roots_;        // "scope0", ... as create_scopes made them
  Churn churn_{ChurnMix{}};
  SimResult result_;
  FaultCounts fault_counts_;  // the faults of plan_faults that took effect
  std::int64_t overlap_since_connected_ = -1;
  std::int64_t overlap_since_partitioned_ = -1;
};

}  // namespace quiver::sim
