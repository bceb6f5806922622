// The simulator's agent host: runs agents' engines on simulated time, their samples carried as
// CDR over the simulated network, kills and restarts them.
#include "quiver/sim/agent_host.h"

#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/hash.h"
#include "quiver/sim/simulator.h"
#include "kept_replica.h"
#include "sim_gateway.h"

namespace quiver::sim {

struct AgentHost::Slot {
  SimAgentSpec spec;
  int incarnation = 0;
  bool up = false;
  std::unique_ptr<graph::Graph> graph;
  std::unique_ptr<agents::schema::SchemaAdmission> schema;  // outlives the replicator
  std::unique_ptr<agents::Replicator> replicator;
  std::unique_ptr<agents::Agent> agent;
  std::unique_ptr<agents::Engine> engine;  // from boot on; runs the agent once it is set up
  bool agent_running = false;
  // Its store (AgentHostOptions::durable): what the replica had joined when it was killed, under
  // the replica incarnation the store keeps (a process restarted from its store keeps it too).
  std::uint64_t replica_incarnation = 0;
  KeptReplica stored;
};

AgentHost::AgentHost(std::vector<SimAgentSpec> agents, AgentHostOptions o)
    : opt_(std::move(o)),
      rng_(opt_.seed),
      net_(static_cast<int>(agents.size() + (opt_.team.robots.size() >= 2 ? 2 * opt_.team.robots.size() : 0)),
           Rng(opt_.seed ^ 0x9e3779b97f4a7c15ULL), opt_.links) {
  for (auto& a : agents) {
    auto s = std::make_unique<Slot>();
    s->spec = std::move(a);
    agents_.push_back(std::move(s));
  }
  if (opt_.team.robots.size() < 2) return;
  // Each robot its own network (segment r), the team network segment R with its own links.
  const int n = static_cast<int>(opt_.team.robots.size());
  for (int r = 0; r < n; ++r) gateways_.push_back(std::make_unique<SimGateway>());
  for (int i = 0; i < size(); ++i) net_.set_segment(i, robot_of(i));
  for (int r = 0; r < n; ++r) {
    net_.set_segment(gateway_node(r, 0), r);
    net_.set_segment(gateway_node(r, 1), n);
  }
  net_.set_segment_faults(n, opt_.team.links);
}

AgentHost::~AgentHost() {
  // Engines first: they refer to the replicas and agents.
  gateways_.clear();
  for (auto& s : agents_) {
    s->engine.reset();
    s->agent.reset();
    s->replicator.reset();
    s->graph.reset();
  }
}

void AgentHost::note(const std::string& line) {
  if (opt_.log) opt_.log(net_.now(), line);
}

Status AgentHost::start() {
  if (!opt_.world_json.empty()) {
    auto seed = graph::world_seed(opt_.world_json, "world");
    if (!seed.ok()) return seed.error();
    world_ = std::make_unique<graph::GraphDelta>(std::move(seed->delta));
  }
  for (int i = 0; i < size(); ++i) boot(i);
  for (int r = 0; r < robots(); ++r) {
    restart_gateway(r);
    net_.at(net_.now() + static_cast<std::int64_t>(rng_.below(static_cast<std::uint64_t>(opt_.tick_ns))),
            [this, r] { tick_gateway(r); });
  }
  return {};
}

// ---- robot teams ----

int AgentHost::robot_index(std::string_view name) const {
  for (int r = 0; r < robots(); ++r)
    if (robot_name(r) == name) return r;
  return -1;
}

int AgentHost::robot_of(int agent) const {
  const int r = agents_[static_cast<std::size_t>(agent)]->spec.robot;
  return robots() > 0 && r >= 0 && r < robots() ? r : 0;
}

bool AgentHost::gateway_up(int r) const { return gateways_[static_cast<std::size_t>(r)]->up; }

graph::Graph* AgentHost::gateway_graph(int r, int side) {
  SimGateway& g = *gateways_[static_cast<std::size_t>(r)];
  return g.up ? g.graph[side].get() : nullptr;
}

agents::Replicator* AgentHost::gateway_replicator(int r, int side) {
  SimGateway& g = *gateways_[static_cast<std::size_t>(r)];
  return g.up ? g.replicator[side].get() : nullptr;
}

// Where robot r's gateway lives: its two network nodes, its name and replica ids.
static SimGateway::Place gateway_place(const AgentHost& host, int r, int node0) {
  SimGateway::Place at;
  at.node[0] = node0;
  at.node[1] = node0 + 1;
  at.name = host.robot_name(r) + "-gateway";
  at.robot = host.robot_name(r);
  at.replica_base = fnv1a64(at.name) & ~std::uint64_t{1};
  return at;
}

void AgentHost::kill_gateway(int r) {
  SimGateway& g = *gateways_[static_cast<std::size_t>(r)];
  if (!g.up) return;
  rejected_ += g.crash(net_, gateway_place(*this, r, gateway_node(r, 0)), opt_.durable);
  note(robot_name(r) + (opt_.durable ? "-gateway killed (kill -9: its store keeps both its replicas)"
                                     : "-gateway killed (kill -9: both its replicas are gone)"));
}

void AgentHost::restart_gateway(int r) {
  SimGateway& g = *gateways_[static_cast<std::size_t>(r)];
  kill_gateway(r);
  const SimGateway::Place at = gateway_place(*this, r, gateway_node(r, 0));
  const bool from_store = g.boot(net_, at, opt_.replicator, [this](const std::string& side, const Error& e) {
    ++rejected_;
    note(side + " rejected: " + e.to_string());
  });
  if (from_store) note(at.name + " restarts (incarnation " + std::to_string(g.incarnation) + " kept, its replicas loaded from its store)");
  else note(at.name + (g.incarnation > 1 ? " restarts (incarnation " + std::to_string(g.incarnation) + ", empty replicas)" : " starts"));
}

void AgentHost::tick_gateway(int r) {
  gateways_[static_cast<std::size_t>(r)]->tick(net_.now());
  net_.at(net_.now() + opt_.tick_ns, [this, r] { tick_gateway(r); });
}

void AgentHost::set_team_loss(double p) {
  if (FaultConfig* f = net_.segment_faults(robots())) f->loss = p;
}

std::uint64_t AgentHost::team_bytes() const {
  const auto& seg = net_.stats().segment_bytes;
  const auto r = static_cast<std::size_t>(robots());
  return robots() > 0 && seg.size() > r ? seg[r] : 0;
}

int AgentHost::index(std::string_view name) const {
  for (int i = 0; i < size(); ++i)
    if (agents_[static_cast<std::size_t>(i)]->spec.name == name) return i;
  return -1;
}

const std::string& AgentHost::name(int i) const { return agents_[static_cast<std::size_t>(i)]->spec.name; }
bool AgentHost::up(int i) const { return agents_[static_cast<std::size_t>(i)]->up; }
int AgentHost::incarnation(int i) const { return agents_[static_cast<std::size_t>(i)]->incarnation; }
agents::Agent* AgentHost::agent(int i) {
  Slot& s = *agents_[static_cast<std::size_t>(i)];
  return s.agent_running ? s.agent.get() : nullptr;
}
graph::Graph* AgentHost::graph(int i) { return agents_[static_cast<std::size_t>(i)]->graph.get(); }
agents::Engine* AgentHost::runtime(int i) {
  Slot& s = *agents_[static_cast<std::size_t>(i)];
  return s.agent_running ? s.engine.get() : nullptr;
}
agents::Replicator* AgentHost::replicator(int i) { return agents_[static_cast<std::size_t>(i)]->replicator.get(); }

void AgentHost::every(std::int64_t period_ns, std::function<void()> fn) {
  repeat(period_ns, std::make_shared<std::function<void()>>(std::move(fn)));
}

void AgentHost::repeat(std::int64_t period_ns, std::shared_ptr<std::function<void()>> fn) {
  net_.at(net_.now() + period_ns, [this, period_ns, fn] {
    (*fn)();
    repeat(period_ns, fn);
  });
}

void AgentHost::boot(int i) {
  Slot& s = *agents_[static_cast<std::size_t>(i)];
  ++s.incarnation;
  s.up = true;
  const int inc = s.incarnation;
  const bool from_store = static_cast<bool>(s.stored);
  if (!from_store) s.replica_incarnation = static_cast<std::uint64_t>(inc);
  s.graph = std::make_unique<graph::Graph>(graph::ReplicaId{fnv1a64(s.spec.name), s.replica_incarnation});
  if (from_store) s.graph->merge(*s.stored.state);
  net_.set_up(i, true);
  net_.set_address(i, s.graph->replica());
  agents::ReplicatorOptions ro = opt_.replicator;
  ro.name = s.spec.name;
  // The network introduces peers as DDS discovery does (a hello then needs only a few answers).
  s.replicator = std::make_unique<agents::Replicator>(*s.graph, net_.endpoint(i), ro);
  if (opt_.schema) {
    s.schema = std::make_unique<agents::schema::SchemaAdmission>(opt_.schema, nullptr);
    s.schema->install(*s.graph, *s.replicator);
  }
  net_.discover(i, {s.graph->replica(), ro.name, ro.observer}, [this, i](const agents::PeerCard& c) {
    if (auto& t = agents_[static_cast<std::size_t>(i)]; t->replicator) t->replicator->introduce(c);
  });
  // The engine runs this replica now, and its agent once it is set up (the same loop as a process).
  agents::EngineOptions eo;
  eo.seed = opt_.seed ^ fnv1a64(s.spec.name) ^ static_cast<std::uint64_t>(inc);
  eo.locks = opt_.locks;
  eo.clock = [this] { return net_.now(); };
  eo.log = [this, i](std::string_view line) { note(name(i) + ": " + std::string(line)); };
  eo.jobs = agents::JobRunner::Mode::kInline;  // a seed replays exactly
  s.engine = std::make_unique<agents::Engine>(*s.graph, s.replicator.get(), std::move(eo));
  s.agent_running = false;
  net_.set_receiver(i, [this, i](const agents::CdrSample& sample, std::int64_t) {
    Slot& t = *agents_[static_cast<std::size_t>(i)];
    auto decoded = agents::decode_cdr_sample(sample.topic, sample.bytes);
    if (decoded.ok()) t.engine->on_sample(*decoded);
    else t.replicator->on_undecodable(decoded.error());
    t.engine->pump();
  });
  s.replicator->on_error([this, i](const Error& e) {
    ++rejected_;
    note(name(i) + " rejected: " + e.to_string());
  });
  if (from_store) {
    s.replicator->restore(s.stored.applied);
    s.stored = KeptReplica{};
  }
  s.replicator->start(net_.now());
  if (world_) (void)s.replicator->seed(*world_);
  note(name(i) + (inc == 1 ? " starts"
                  : " restarts (incarnation " + std::to_string(inc) +
                        (from_store ? ", its replica loaded from its store under incarnation " +
                                          std::to_string(s.replica_incarnation) + ")"
                                    : ", empty replica)")));
  net_.at(net_.now() + static_cast<std::int64_t>(rng_.below(static_cast<std::uint64_t>(opt_.tick_ns))),
          [this, i, inc] { tick(i, inc); });
  net_.at(net_.now() + opt_.join_wait_ns, [this, i, inc] { try_setup(i, inc, net_.now() + 4 * opt_.join_wait_ns); });
}

void AgentHost::try_setup(int i, int inc, std::int64_t give_up_at) {
  Slot& s = *agents_[static_cast<std::size_t>(i)];
  if (!s.up || s.incarnation != inc || s.agent) return;
  // Join the peers first, so that setup() sees the shared graph (as the process host does).
  const bool ready = s.replicator->live_peer_count() == 0 || s.replicator->synced();
  if (!ready && net_.now() < give_up_at) {
    net_.at(net_.now() + 20'000'000, [this, i, inc, give_up_at] { try_setup(i, inc, give_up_at); });
    return;
  }
  s.agent = s.spec.make();
  s.engine->attach(*s.agent);
  s.engine->on_action_event([this, i](const agents::ActionEvent& e) {
    if (action_cb_) action_cb_(i, e);
  });
  if (Status st = s.engine->start(); !st.ok()) {
    note(name(i) + " could not start: " + st.error().to_string());
    // An engine holds the agent it ran: both go, and the replica runs on under a fresh one.
    s.engine.reset();
    s.agent.reset();
    agents::EngineOptions eo;
    eo.clock = [this] { return net_.now(); };
    eo.jobs = agents::JobRunner::Mode::kInline;
    s.engine = std::make_unique<agents::Engine>(*s.graph, s.replicator.get(), std::move(eo));
    return;
  }
  s.agent_running = true;
  if (started_cb_) started_cb_(i);
}

void AgentHost::tick(int i, int inc) {
  Slot& s = *agents_[static_cast<std::size_t>(i)];
  if (!s.up || s.incarnation != inc) return;
  s.engine->step();
  net_.at(net_.now() + opt_.tick_ns, [this, i, inc] { tick(i, inc); });
}

void AgentHost::kill(int i) {
  Slot& s = *agents_[static_cast<std::size_t>(i)];
  if (!s.up) return;
  s.up = false;
  net_.set_up(i, false);
  if (opt_.durable && s.graph && s.replicator) {
    s.stored = KeptReplica::of(*s.graph, *s.replicator);
  }
  s.engine.reset();
  s.agent_running = false;
  s.agent.reset();
  s.replicator.reset();
  s.graph.reset();
  note(name(i) + (opt_.durable ? " killed (kill -9: its devices are gone; its store keeps its replica)"
                                : " killed (kill -9: its replica and devices are gone)"));
}

bool AgentHost::kill(const std::string& agent) {
  for (int r = 0; r < robots(); ++r) {
    if (agent == robot_name(r) + "-gateway") {
      if (!gateway_up(r)) return false;
      kill_gateway(r);
      return true;
    }
    if (agent == robot_name(r)) {  // the whole robot: every process at once
      note("robot " + agent + " crashes: all its processes are killed");
      kill_gateway(r);
      for (int i = 0; i < size(); ++i)
        if (robot_of(i) == r) kill(i);
      return true;
    }
  }
  const int i = index(agent);
  if (i < 0 || !up(i)) return false;
  kill(i);
  return true;
}

bool AgentHost::restart(const std::string& agent) {
  for (int r = 0; r < robots(); ++r) {
    if (agent == robot_name(r) + "-gateway") {
      if (gateway_up(r)) return false;
      restart_gateway(r);
      return true;
    }
    if (agent == robot_name(r)) {
      if (!gateway_up(r)) restart_gateway(r);
      for (int i = 0; i < size(); ++i)
        if (robot_of(i) == r && !up(i)) boot(i);
      return true;
    }
  }
  const int i = index(agent);
  if (i < 0 || up(i)) return false;
  restart(i);
  return true;
}

void AgentHost::restart(int i) {
  if (agents_[static_cast<std::size_t>(i)]->up) kill(i);
  boot(i);
}

void AgentHost::partition(const std::vector<std::vector<std::string>>& groups) {
  bool robots_named = robots() > 0 && !groups.empty();
  for (const auto& g : groups)
    for (const std::string& n : g) robots_named = robots_named && robot_index(n) >= 0;
  if (robots_named) {
    // The team network splits; each robot's own network stays whole.
    for (int r = 0; r < robots(); ++r) net_.set_group(gateway_node(r, 1), static_cast<int>(groups.size()) + 1);
    for (std::size_t g = 0; g < groups.size(); ++g)
      for (const std::string& n : groups[g]) net_.set_group(gateway_node(robot_index(n), 1), static_cast<int>(g) + 1);
  } else {
    for (int i = 0; i < size(); ++i) net_.set_group(i, static_cast<int>(groups.size()) + 1);
    for (std::size_t g = 0; g < groups.size(); ++g)
      for (const std::string& n : groups[g])
        if (int i = index(n); i >= 0) net_.set_group(i, static_cast<int>(g) + 1);
  }
  std::string desc;
  for (const auto& g : groups) {
    desc += desc.empty() ? "{" : " | {";
    for (std::size_t k = 0; k < g.size(); ++k) desc += (k ? "," : "") + g[k];
    desc += "}";
  }
  note("partition " + desc);
}

}  // namespace quiver::sim
