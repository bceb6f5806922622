// The process host: one agent as its own OS process over Cyclone DDS, run from the standard flags until SIGINT
// or SIGTERM.
#include "quiver/agents/runtime/process/process_host.h"

#include <CLI/CLI.hpp>

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/replica_reports.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/agents/runtime/process/security_setup.h"
#include "quiver/graph/world_file.h"

namespace quiver::agents::inline runtime {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

nlohmann::json status(Agent& agent, DdsReplica& r, const Engine& rt) {
  const auto& st = r.replicator().stats();
  nlohmann::json j;
  j["name"] = agent.name();
  j["replica"] = r.id().to_string();
  j["nodes"] = r.graph().node_count();
  j["edges"] = r.graph().edge_count();
  j["digest"] = r.graph().digest().hex();
  j["peers"] = r.replicator().live_peer_count();
  j["synced"] = r.replicator().synced();
  j["published"] = r.replicator().last_seq();  // the last sequence number it published
  j["published_bytes"] = st.bytes_published;    // the encoded changes it published
  j["deltas_applied"] = st.deltas_applied;
  j["states_applied"] = st.states_applied;
  j["pulls_sent"] = st.pulls_sent;  // with states_applied: a state transfer is under way (crash tests)
  j["state_answers"] = st.pulls_answered_with_state;
  j["write_timeouts"] = r.transport().stats().write_timeouts;
  j["rejected"] = st.rejected;
  j["equivocations"] = st.equivocations;
  j["divergences"] = st.divergences;
  j["refused"] = st.deltas_refused + st.states_refused;  // by the permissions (docs/security.md) or the schema (docs/schema.md)
  j["peers_known"] = r.replicator().peers().size();
  j["rss_kb"] = resident_kb();
  j["actions_started"] = rt.stats().started;
  j["actions_finished"] = rt.stats().finished;
  j["actions_cancelled"] = rt.stats().cancelled;
  j["t_ms"] = monotonic_ns() / 1'000'000;
  if (Store* s = r.store()) {
    const StoreStats ss = s->stats();
    j["store_records"] = ss.records_appended;
    j["store_syncs"] = ss.syncs;
    j["store_compactions"] = ss.compactions;
    j["store_ok"] = s->health().ok();
  }
  agent.status(j);
  return j;
}

}  // namespace

void request_stop() { g_stop.store(true); }

bool stop_requested() { return g_stop.load(); }

void stop_on_signals() {
  g_stop.store(false);
  install_signal_handlers();
}

long resident_kb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

void ProcessFlags::add_dds(CLI::App* cmd) {
  cmd->add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 230))->capture_default_str();
  cmd->add_option("--dds-config", dds_config,
                  "loopback (default: 127.0.0.1 only, multicast off), env (opt-in: use CYCLONEDDS_URI), "
                  "or the path of a Cyclone XML file (opt-in, e.g. for several hosts)")
      ->capture_default_str();
  cmd->add_option("--loss-permille", loss_permille, "testing: Cyclone drops this share of sent packets")
      ->check(CLI::Range(0, 999));
  cmd->add_option("--lease", lease_s,
                  "DDS participant lease in seconds: a crashed or cut-off agent is noticed within it; each "
                  "process receives a few discovery packets per peer per lease (longer for many processes; "
                  "from 5 s Cyclone is also paced for them: docs/protocol.md)")
      ->check(CLI::Range(0.05, 600.0))
      ->capture_default_str();
  cmd->add_option("--membership", membership,
                  "all-to-all (every heartbeat, this replica's whole (origin, seq) set to every peer) or gossip "
                  "(constant-size beats to one peer per period: the cost per agent does not grow with the number "
                  "of agents; docs/protocol.md)")
      ->check(CLI::IsMember({"all-to-all", "gossip"}))
      ->capture_default_str();
  cmd->add_option("--security", security,
                  "DDS Security and graph-level permissions: the credentials directory of `quiver keys`; the "
                  "agent authenticates under its name, signs its deltas, and meets only agents of the same CA "
                  "(docs/security.md)");
  cmd->add_option("--schema", schema,
                  "the shared vocabulary (node types, edge types, attributes) every agent of the domain loads: "
                  "checked on every commit and every change received (docs/schema.md)")
      ->check(CLI::ExistingFile);
}

void ProcessFlags::add_all(CLI::App* cmd) {
  add_dds(cmd);
  cmd->add_option("--world", world, "seed the shared graph from this JSON world file (idempotent)");
  cmd->add_option("--seed", seed, "the agent's random seed")->check(CLI::NonNegativeNumber);
  cmd->add_option("--status-ms", status_ms, "print a JSON status line this often")->check(CLI::Range(0, 3'600'000));
  cmd->add_flag("!--no-final-status", final_status,
                "print no status line after a clean stop (by default one is printed, whatever --status-ms says)");
  cmd->add_option("--run-for", run_for_s, "exit after this many seconds (default 0: until SIGINT/SIGTERM)")
      ->check(CLI::Range(0.0, 1e7));
  cmd->add_option("--join-wait", join_wait_s, "before starting, wait this long to join the peers")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  cmd->add_option("--hang", hang_s,
                  "report an agent callback that has not returned after this many seconds (the agent stays "
                  "alive for its peers meanwhile; 0: never)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  cmd->add_option("--hand-over", hand_over_s,
                  "on a clean stop, keep replicating up to this long until every live peer holds all this agent "
                  "published (0: leave at once)")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  cmd->add_option("--store", store,
                  "keep the replica in this directory (LMDB): reloaded on start, so the agent rejoins and "
                  "pulls only what it missed (docs/persistence.md)");
  cmd->add_option("--durability", durability,
                  "with --store: when the log reaches the disk: none (never flushed by us), batch (flushed "
                  "every 20 ms, after publishing), always (flushed before a commit returns and is published)")
      ->check(CLI::IsMember({"none", "batch", "always"}))
      ->capture_default_str();
  cmd->add_option("--store-compact-mb", store_compact_mb,
                  "with --store: fold the log into a new snapshot once it holds this many MiB (and more than "
                  "the snapshot); 0: never")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
}

Status ProcessFlags::apply_to(DdsConfig& c) const {
  c.domain = domain;
  c.xmit_loss_permille = loss_permille;
  c.lease_ns = static_cast<std::int64_t>(lease_s * 1e9);
  if (dds_config == "loopback") {
    c.source = DdsConfig::Source::kLoopback;
  } else if (dds_config == "env") {
    c.source = DdsConfig::Source::kEnvironment;
  } else {
    std::ifstream in(dds_config);
    if (!in) return make_error(ErrorCode::kIo, "--dds-config: cannot read '" + dds_config + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    c.source = DdsConfig::Source::kXml;
    c.xml = ss.str();
  }
  return {};
}

Status ProcessFlags::apply_schema(DdsReplicaOptions& o) const {
  if (schema.empty()) return {};
  auto s = schema::Schema::load(schema);
  if (!s.ok()) return make_error(s.error().code, "--schema: " + s.error().message);
  o.schema = std::make_shared<const schema::Schema>(std::move(*s));
  return {};
}

Status ProcessFlags::check() const {
  if (membership != "gossip" && membership != "all-to-all")
    return make_error(ErrorCode::kInvalidArgument, "--membership: '" + membership + "' is neither gossip nor all-to-all");
  if (auto d = parse_durability(durability); !d.ok()) return make_error(d.error().code, "--durability: " + d.error().message);
  if (!(lease_s > 0)) return make_error(ErrorCode::kInvalidArgument, "--lease: must be positive");
  if (!(hand_over_s >= 0)) return make_error(ErrorCode::kInvalidArgument, "--hand-over: must not be negative");
  if (!(store_compact_mb > 0)) return make_error(ErrorCode::kInvalidArgument, "--store-compact-mb: must be positive");
  return {};
}

Result<DdsReplicaOptions> replica_options(const std::string& name, const ProcessFlags& f) {
  if (Status s = f.check(); !s.ok()) return s.error();
  DdsReplicaOptions o;
  o.name = name;
  f.apply_to(o.replicator);
  if (Status s = f.apply_to(o.dds); !s.ok()) return s.error();
  if (!f.security.empty())
    if (Status s = enable_security(o, f.security); !s.ok())
      return make_error(s.error().code, "--security: " + s.error().message);
  if (Status s = f.apply_schema(o); !s.ok()) return s.error();
  if (!f.store.empty()) {
    StoreOptions so;
    so.dir = f.store;
    so.durability = *parse_durability(f.durability);  // checked above
    so.compact_log_bytes = static_cast<std::size_t>(f.store_compact_mb * (1 << 20));
    o.store = so;
  }
  o.engine.seed = f.seed;  // mixed with the incarnation by DdsReplica::create()
  return o;
}

int run_process(Agent& agent, const ProcessFlags& f, Error* why_not_started) {
  g_stop.store(false);  // a stop requested for an earlier run in this process is not this run's
  auto log = named_logger(agent.name());
  // Could not start: logged, told the caller, exit status 2.
  auto not_started = [&](const Error& e) {
    log->error("{}", e.to_string());
    if (why_not_started != nullptr) *why_not_started = e;
    return 2;
  };
  auto options = replica_options(agent.name(), f);
  if (!options.ok()) {
    return not_started(options.error());
  }
  DdsReplicaOptions& o = *options;
  o.engine.log = [&](std::string_view line) { log->info("{}", line); };
  o.engine.warn = [&](std::string_view line) { log->warn("{}", line); };
  auto created = DdsReplica::create(o);
  if (!created.ok()) {
    return not_started(created.error());
  }
  DdsReplica& r = **created;
  if (r.store_recovery())
    log->error("{}: the store was set aside and the replica starts empty, to be filled by its peers",
               r.store_recovery()->to_string());
  if (Store* s = r.store(); s != nullptr && !s->opening().torn_tail.empty())
    log->error("{}", s->opening().torn_tail);
  if (Store* s = r.store())
    log->info("store {} ({}): {} records replayed, snapshot {} bytes, {} incarnation", f.store, f.durability,
              s->opening().records, s->opening().snapshot_bytes,
              s->opening().created ? "new store, new" : s->opening().incarnation_kept ? "kept its" : "a new");
  install_signal_handlers();
  ReplicaReports reports(log);
  reports.attach(r.replicator());
  route_dds_log([&](const std::string& line) { reports.report(make_error(ErrorCode::kTransport, "DDS: " + line)); });
  struct Unroute {
    ~Unroute() { route_dds_log(nullptr); }  // before `reports` goes, on every return
  } unroute;
  log->info("replica {} on DDS domain {} ({})", r.id().to_string(), f.domain, f.dds_config);
  if (!f.world.empty() || !f.world_text.empty()) {
    // A seed depends only on the file: agents started together with it hold one world.
    auto seed = f.world.empty() ? graph::world_seed(f.world_text, "embedded world") : graph::world_seed_file(f.world);
    if (!seed.ok()) {
      return not_started(seed.error());
    }
    auto fresh = r.replicator().seed(seed->delta);
    log->info("world {} ({} nodes, {} edges, {} RT edges) {}", f.world, seed->info.nodes, seed->info.edges,
              seed->info.rt_edges, fresh.ok() && *fresh ? "seeded" : "already held");
  }
  // Join the peers first, so that setup() sees the shared graph.
  const auto wait = static_cast<std::int64_t>(f.join_wait_s * 1e9);
  if (wait > 0) {
    r.spin_until([&] { return r.replicator().live_peer_count() > 0 || g_stop.load(); }, wait);
    if (r.replicator().live_peer_count() > 0)
      r.spin_until([&] { return r.replicator().synced() || g_stop.load(); }, 4 * wait);
  }
  // The engine runs the agent on this thread (the owner); a keeper thread keeps it alive for its
  // peers while one of its callbacks blocks, and reports a callback that does not return.
  Engine& rt = r.engine();
  rt.attach(agent);
  if (Status s = rt.start(); !s.ok()) {
    return not_started(s.error());
  }
  if (rt.guard())
    rt.guard()->on_violation([&](const Violation& v) { log->warn("violation {}", v.to_string(r.graph())); });
  r.keep_alive(
      static_cast<std::int64_t>(f.hang_s * 1e9), [&](const std::string& line) { log->warn("{}", line); },
      [&](const std::string& line) { log->info("{}", line); });
  const std::int64_t start = monotonic_ns();
  std::int64_t next_status = start;
  while (!g_stop.load()) {
    std::int64_t now = monotonic_ns();
    if (f.run_for_s > 0 && now - start > static_cast<std::int64_t>(f.run_for_s * 1e9)) break;
    // The round itself decides how long it waits (its tick, timers, traffic); a signal's stop is
    // seen within the quiet round.
    r.spin_once(f.status_ms > 0 ? std::min<std::int64_t>(100'000'000, f.status_ms * 1'000'000LL) : 100'000'000);
    now = monotonic_ns();
    reports.tick(now);
    if (f.status_ms > 0 && now >= next_status) {
      std::cout << status(agent, r, rt).dump() << std::endl;
      next_status = now + f.status_ms * 1'000'000LL;
    }
  }
  rt.stop();
  // A clean stop hands over: what this replica holds (its last commits, and whatever its peers
  // missed while they were away) reaches them before it leaves; it could be the only holder.
  const auto hand_over = static_cast<std::int64_t>(f.hand_over_s * 1e9);
  if (hand_over > 0 && !r.hand_over(hand_over))
    log->warn("left before every peer held all this replica holds (--hand-over {} s)", f.hand_over_s);
  if (f.final_status) std::cout << status(agent, r, rt).dump() << std::endl;
  return 0;
}

int run_process(Agent& agent, int argc, char** argv) {
  CLI::App app{"quiver agent process: " + agent.name()};
  ProcessFlags f;
  f.add_all(&app);
  CLI11_PARSE(app, argc, argv);
  return run_process(agent, f);
}

}  // namespace quiver::agents
