#pragma once
/// @file
/// The simulator as a host of agents (agents/runtime): many agents at once, each with its own
/// replica, replicator and runtime, joined by the virtual network (network.h) in virtual time.
/// Agents run exactly the code they run as processes; the host gives them the virtual clock, a
/// seeded random source, and the faults: partitions, packet loss, kill -9 (the agent and its
/// replica vanish) and restart (a fresh incarnation with an empty replica that rejoins).
/// Deterministic: one seed replays a run exactly.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/rules/schema/schema.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/network.h"

namespace quiver::sim {

struct SimAgentSpec {
  std::string name;
  /// Makes the agent (again, on every restart).
  std::function<std::unique_ptr<agents::Agent>()> make;
  /// A team (AgentHostOptions::team): the index of the robot it runs on.
  int robot = 0;
};

struct AgentHostOptions {
  std::uint64_t seed = 1;
  FaultConfig links;                      ///< delays and base faults of every link
  agents::ReplicatorOptions replicator;   ///< defaults: SimConfig::default_replicator()
  agents::LockOptions locks;
  std::int64_t tick_ns = 10'000'000;
  std::int64_t join_wait_ns = 300'000'000;  ///< before a (re)started agent's setup(): to sync first
  std::string world_json;                   ///< seeded into every replica at boot (may be empty)
  /// The shared vocabulary every agent loads (docs/schema.md): checked on commit and merge. Null: none.
  std::shared_ptr<const agents::schema::Schema> schema;
  std::function<void(std::int64_t t_ns, const std::string& line)> log;
  /// A robot team (docs/teams.md): each agent on its robot's own network (SimAgentSpec::robot),
  /// one gateway per robot (`NAME-gateway`: two replicas and a bridge, as `quiver gateway` runs
  /// them) joining it to the team network, whose links have their own faults.
  /// Agents and gateways with stores (`--durability always`, `quiver gateway --store`): kill -9
  /// keeps everything the replicas had joined, and a restart loads it under the incarnation the
  /// store kept, as a restarted process does (its peers then send only what it lacks). Without:
  /// a restart is empty, under a new incarnation.
  bool durable = false;
  struct Team {
    std::vector<std::string> robots;  ///< the robots' names; fewer than two: one network
    FaultConfig links;                ///< the team network's delays and base faults
  } team;
};

struct SimGateway;

class AgentHost final : public FaultTarget {
 public:
  AgentHost(std::vector<SimAgentSpec> agents, AgentHostOptions o);
  ~AgentHost();
  AgentHost(const AgentHost&) = delete;
  AgentHost& operator=(const AgentHost&) = delete;

  /// Boots every agent. @returns the world file's error, if any.
  Status start();
  std::int64_t now() const override { return net_.now(); }
  void run_until(std::int64_t t_ns) { net_.run_until(t_ns); }
  /// Runs `fn` every `period_ns` of virtual time (observers and checks).
  void every(std::int64_t period_ns, std::function<void()> fn);
  void at(std::int64_t t_ns, std::function<void()> fn) override { net_.at(t_ns, std::move(fn)); }

  int size() const { return static_cast<int>(agents_.size()); }
  /// The index of the agent called `name`, or -1.
  int index(std::string_view name) const;
  const std::string& name(int i) const;
  bool up(int i) const;
  /// While up: the agent, its replica, its runtime (null while down or before its setup()).
  agents::Agent* agent(int i);
  graph::Graph* graph(int i);
  /// The engine running agent i (null while down or before its setup()).
  agents::Engine* runtime(int i);
  agents::Replicator* replicator(int i);
  int incarnation(int i) const;

  /// kill -9: the agent, its devices and its replica vanish at once (no teardown, no goodbye);
  /// with `durable`, its store keeps what the replica had joined.
  void kill(int i);
  /// Boots it again: a fresh incarnation with an empty replica, or loaded from its store under
  /// the incarnation the store kept (`durable`). incarnation() counts the boots.
  void restart(int i);
  /// Agents hear each other only within a group; agents not named form one more group. In a
  /// team, groups naming robots cut the team network between them (the robots' own networks stay
  /// whole; robots not named form one more group).
  void partition(const std::vector<std::vector<std::string>>& groups) override;
  void heal() override { net_.heal(); }
  /// Loss on every link; in a team, on the team network only (the robots' own networks are
  /// their loopbacks).
  void set_loss(double p) override {
    if (robots() > 0) set_team_loss(p);
    else net_.faults().loss = p;
  }
  /// FaultTarget by name: kill -9 / restart of the agent called `agent` (false: not running /
  /// already running, or no such agent). In a team also `NAME-gateway` (a robot's gateway) and
  /// `NAME` (a robot: all its agents and its gateway at once).
  bool kill(const std::string& agent) override;
  bool restart(const std::string& agent) override;
  VirtualNetwork& network() { return net_; }

  // ---- robot teams (AgentHostOptions::team) ----
  int robots() const { return static_cast<int>(gateways_.size()); }
  const std::string& robot_name(int r) const { return opt_.team.robots[static_cast<std::size_t>(r)]; }
  /// The robot called `name`, or -1.
  int robot_index(std::string_view name) const;
  int robot_of(int agent) const;
  bool gateway_up(int r) const;
  /// Side 0 (the robot's network) or 1 (the team's) of robot r's gateway (null while down).
  graph::Graph* gateway_graph(int r, int side);
  agents::Replicator* gateway_replicator(int r, int side);
  /// kill -9 of robot r's gateway (both replicas vanish), and its restart (empty).
  void kill_gateway(int r);
  void restart_gateway(int r);
  /// Loss on the team network only (the robots' own networks keep theirs).
  void set_team_loss(double p);
  /// Bytes sent on the team network so far.
  std::uint64_t team_bytes() const;

  /// Every action event of every agent (index, event).
  void on_action_event(std::function<void(int, const agents::ActionEvent&)> cb) { action_cb_ = std::move(cb); }
  /// Called right after an agent's runtime started (its setup() ran).
  void on_agent_started(std::function<void(int)> cb) { started_cb_ = std::move(cb); }
  std::uint64_t rejected() const { return rejected_; }

 private:
  struct Slot;
  void boot(int i);
  void try_setup(int i, int incarnation, std::int64_t give_up_at);
  void tick(int i, int incarnation);
  void note(const std::string& line);
  void repeat(std::int64_t period_ns, std::shared_ptr<std::function<void()>> fn);
  void tick_gateway(int r);
  int gateway_node(int r, int side) const { return size() + 2 * r + side; }

  AgentHostOptions opt_;
  Rng rng_;
  VirtualNetwork net_;
  std::vector<std::unique_ptr<Slot>> agents_;
  std::vector<std::unique_ptr<SimGateway>> gateways_;  // one per robot of a team
  std::unique_ptr<graph::GraphDelta> world_;
  std::function<void(int, const agents::ActionEvent&)> action_cb_;
  std::function<void(int)> started_cb_;
  std::uint64_t rejected_ = 0;
};

}  // namespace quiver::sim
