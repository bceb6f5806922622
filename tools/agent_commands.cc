// quiver agent: a replicating agent process. quiver dump: an observer that prints the graph.

#include <unistd.h>

#include <csignal>
#include <mutex>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "dds_options.h"
#include "quiver/agents/dds/dds_replica.h"
#include "quiver/agents/replication/error_limiter.h"
#include "quiver/agents/grammar/grammar_guard.h"
#include "quiver/graph/world_file.h"
#include "quiver/rng.h"
#include "quiver/sim/workload.h"

namespace quiver::tools {
namespace {

using agents::DdsReplica;
using agents::monotonic_ns;

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

// Resident memory of this process (Linux), for the status line: the rogue tests watch it.
long resident_kb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

nlohmann::json status(DdsReplica& a, bool churning) {
  const auto& st = a.replicator().stats();
  nlohmann::json j;
  j["name"] = a.options().name;
  j["replica"] = a.id().to_string();
  j["nodes"] = a.graph().node_count();
  j["edges"] = a.graph().edge_count();
  j["digest"] = a.graph().digest().hex();
  j["peers"] = a.replicator().live_peer_count();
  j["synced"] = a.replicator().synced();
  j["deltas_applied"] = st.deltas_applied;
  j["states_applied"] = st.states_applied;
  j["write_timeouts"] = a.transport().stats().write_timeouts;
  j["rejected"] = st.rejected_packets;
  j["equivocations"] = st.equivocations;
  j["peers_known"] = a.replicator().peers().size();
  j["rss_kb"] = resident_kb();
  j["churning"] = churning;
  j["t_ms"] = monotonic_ns() / 1'000'000;
  return j;
}

struct AgentFlags {
  std::string name;
  std::string world;
  std::string grammar;
  DdsFlags dds;
  double churn_hz = 0;
  double churn_for_s = 0;
  std::uint64_t seed = 1;
  int status_ms = 0;
  double run_for_s = 0;
};

int run_agent(const AgentFlags& f) {
  agents::DdsReplicaOptions o;
  o.name = f.name;
  auto created = f.dds.create_agent(o);
  if (!created.ok()) {
    std::fprintf(stderr, "quiver agent: %s\n", created.error().to_string().c_str());
    return 2;
  }
  DdsReplica& a = **created;
  install_signal_handlers();

  // A hostile peer can send thousands of bad packets a second: one line per kind of error, and
  // a count of the rest every few seconds.
  // Cyclone's own warnings (malformed packets, samples that do not deserialize) go the same way;
  // they come from its threads, hence the lock.
  std::mutex errors_mu;
  agents::ErrorLimiter errors([&](const std::string& line) {
    std::fprintf(stderr, "quiver agent %s: rejected: %s\n", f.name.c_str(), line.c_str());
  });
  auto report = [&](const Error& e) {
    std::lock_guard<std::mutex> lock(errors_mu);
    errors.report(e, monotonic_ns());
  };
  a.replicator().on_error(report);
  // Peers coming and going: a handful per 5 s are named, invented ones by the thousand are not.
  agents::ErrorLimiter membership([&](const std::string& line) {
    std::fprintf(stderr, "quiver agent %s: %s\n", f.name.c_str(), line.c_str());
  }, 5'000'000'000, 8);
  a.replicator().on_membership([&](agents::Membership m, const agents::PeerInfo& p) {
    const char* what = m == agents::Membership::kJoined ? "joined" : "left";
    membership.report(what, std::string(what) + ": " + p.name + " (" + p.id.to_string() + ")", monotonic_ns());
  });
  agents::route_dds_log([&](const std::string& line) { report(make_error(ErrorCode::kTransport, "DDS: " + line)); });
  struct Unroute {
    ~Unroute() { agents::route_dds_log(nullptr); }  // before `errors` goes, on every return
  } unroute;
  std::fprintf(stderr, "quiver agent %s: replica %s on DDS domain %u (%s)\n", f.name.c_str(), a.id().to_string().c_str(),
               f.dds.domain, f.dds.config.c_str());
  if (!f.world.empty()) {
    // The seed is a delta that depends only on the file: agents started together with the same
    // world seed it once between them, however their starts interleave.
    auto seed = graph::world_seed_file(f.world);
    if (!seed.ok()) {
      std::fprintf(stderr, "quiver agent: %s\n", seed.error().to_string().c_str());
      return 2;
    }
    auto fresh = a.replicator().seed(seed->delta);
    std::fprintf(stderr, "quiver agent %s: world %s (%zu nodes, %zu edges, %zu RT edges) %s\n", f.name.c_str(),
                 f.world.c_str(), seed->info.nodes, seed->info.edges, seed->info.rt_edges,
                 fresh.ok() && *fresh ? "seeded" : "already held");
  }
  // The grammar guards changes made from now on; the seed world is the initial state.
  std::unique_ptr<agents::GrammarGuard> guard;
  if (!f.grammar.empty()) {
    auto g = agents::load_grammar_file(f.grammar);
    if (!g.ok()) {
      std::fprintf(stderr, "quiver agent: %s\n", g.error().to_string().c_str());
      return 2;
    }
    guard = std::make_unique<agents::GrammarGuard>(a.graph(), agents::GrammarChecker(std::move(*g)), f.name);
    guard->install();
    guard->on_violation([&](const agents::Violation& v) {
      std::fprintf(stderr, "quiver agent %s: violation %s\n", f.name.c_str(), v.to_string(a.graph()).c_str());
    });
    guard->on_unverified([&](const graph::ReplicaId& from, const Error& e) {
      std::fprintf(stderr, "quiver agent %s: unverified change from %s: %s\n", f.name.c_str(), from.to_string().c_str(),
                   e.message.c_str());
    });
  }
  Rng rng(f.seed ^ a.id().incarnation);
  sim::Churn churn;
  const std::int64_t start = monotonic_ns();
  std::int64_t next_churn = start, next_status = start;
  const std::int64_t churn_period = f.churn_hz > 0 ? static_cast<std::int64_t>(1e9 / f.churn_hz) : 0;
  auto churning = [&](std::int64_t now) {
    return churn_period > 0 && (f.churn_for_s <= 0 || now - start < f.churn_for_s * 1e9);
  };
  while (!g_stop.load()) {
    std::int64_t now = monotonic_ns();
    if (f.run_for_s > 0 && now - start > static_cast<std::int64_t>(f.run_for_s * 1e9)) break;
    if (churning(now) && now >= next_churn) {
      churn.step(a.graph(), rng, now);
      next_churn += churn_period;
    }
    if (f.status_ms > 0 && now >= next_status) {
      std::cout << status(a, churning(now)).dump() << std::endl;
      next_status = now + f.status_ms * 1'000'000LL;
    }
    a.spin_once(churn_period > 0 ? std::min<std::int64_t>(churn_period, 20'000'000) : 20'000'000);
    if (guard) guard->tick();
    {
      std::lock_guard<std::mutex> lock(errors_mu);
      errors.tick(monotonic_ns());
    }
    membership.tick(monotonic_ns());
  }
  std::cout << status(a, false).dump() << std::endl;
  return 0;
}

struct DumpFlags {
  DdsFlags dds;
  bool json = false;
  bool digest = false;
  double timeout_s = 10;
};

void print_graph(const graph::Graph& g) {
  for (graph::NodeId id : g.nodes()) {
    std::cout << g.name_of(id) << " : " << g.type_of(id).str();
    if (auto p = g.rt_parent(id)) std::cout << "   (RT parent " << g.name_of(*p) << ")";
    std::cout << "\n";
    for (graph::Symbol a : g.attr_names(id)) {
      auto values = g.attr_values(id, a);
      std::cout << "    " << a.str() << " = " << values[0].value.to_string();
      if (values.size() > 1) std::cout << "   [" << values.size() << " concurrent values]";
      std::cout << "\n";
    }
    for (const graph::EdgeKey& k : g.edges_from(id))
      if (!(k.type == graph::symbols::rt())) std::cout << "    -[" << k.type.str() << "]-> " << g.name_of(k.to) << "\n";
  }
}

int run_dump(const DumpFlags& f) {
  agents::DdsReplicaOptions o;
  o.name = "quiver-dump";
  o.observer = true;
  auto created = f.dds.create_agent(o);
  if (!created.ok()) {
    std::fprintf(stderr, "quiver dump: %s\n", created.error().to_string().c_str());
    return 2;
  }
  DdsReplica& a = **created;
  const std::int64_t timeout = static_cast<std::int64_t>(f.timeout_s * 1e9);
  if (!a.spin_until([&] { return a.replicator().live_peer_count() > 0; }, timeout)) {
    std::fprintf(stderr, "quiver dump: no agent answered on DDS domain %u within %.1f s\n", f.dds.domain, f.timeout_s);
    return 1;
  }
  // Synced = we hold everything every live peer says it holds; require it to stay so briefly.
  std::int64_t synced_since = -1;
  bool ok = a.spin_until(
      [&] {
        if (!a.replicator().synced()) {
          synced_since = -1;
          return false;
        }
        if (synced_since < 0) synced_since = monotonic_ns();
        return monotonic_ns() - synced_since > 150'000'000;
      },
      timeout);
  if (!ok) {
    std::fprintf(stderr, "quiver dump: could not sync with the %zu live agents within %.1f s\n",
                 a.replicator().live_peer_count(), f.timeout_s);
    return 1;
  }
  if (f.digest) std::cout << a.graph().digest().hex() << std::endl;
  else if (f.json) std::cout << graph::save_world(a.graph());
  else print_graph(a.graph());
  return 0;
}

}  // namespace

void add_agent_commands(CLI::App& app) {
  auto af = std::make_shared<AgentFlags>();
  auto* agent = app.add_subcommand("agent", "Run a replicating agent (one replica, Cyclone DDS, no executive)");
  agent->add_option("--name", af->name, "agent name (its id derives from it)")->required();
  agent->add_option("--world", af->world, "seed the graph from a JSON world file (names already present are kept)");
  agent->add_option("--grammar", af->grammar, "check every local change against this grammar file (docs/grammar.md)");
  af->dds.add_to(agent);
  agent->add_option("--churn-hz", af->churn_hz, "testing: make random changes at this many transactions per second")
      ->check(CLI::Range(0.0, 100000.0));
  agent->add_option("--churn-for", af->churn_for_s, "testing: stop the random changes after this many seconds")
      ->check(CLI::Range(0.0, 1e7));
  agent->add_option("--seed", af->seed, "testing: seed of the random changes")->check(CLI::NonNegativeNumber);
  agent->add_option("--status-ms", af->status_ms, "print a JSON status line this often")
      ->check(CLI::Range(0, 3'600'000));
  agent->add_option("--run-for", af->run_for_s, "exit after this many seconds (default 0: until SIGINT/SIGTERM)")
      ->check(CLI::Range(0.0, 1e7));
  agent->callback([af] { set_exit_code(run_agent(*af)); });

  auto df = std::make_shared<DumpFlags>();
  auto* dump = app.add_subcommand("dump", "Join as an observer, wait until synced, print the graph and leave");
  df->dds.add_to(dump);
  auto* fmt = dump->add_option_group("format");
  fmt->add_flag("--json", df->json, "print a JSON world file");
  fmt->add_flag("--digest", df->digest, "print the state digest only");
  fmt->require_option(0, 1);
  dump->add_option("--timeout", df->timeout_s, "give up after this many seconds")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  dump->callback([df] { set_exit_code(run_dump(*df)); });
}

}  // namespace quiver::tools
