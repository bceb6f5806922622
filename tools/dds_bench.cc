// quiver bench dds / dds-tracking: multi-process benchmarks of the DDS transport.
//
// The coordinator (the `bench` command) spawns one writer and K reader processes of this same
// binary (hidden `bench-dds-role` command). Phases are coordinated in-band, through a control
// node of the replicated graph. All processes share CLOCK_MONOTONIC, so one-way latencies are
// measured directly: the writer stores its clock in the value it writes, readers subtract it
// from their clock in their change-event callback.

#include <httplib.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <atomic>
#include <memory>
#include <thread>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numeric>

#include "bench_stats.h"
#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "dds_options.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/replica/security/keys.h"
#include "quiver/graph/graph.h"
#include "quiver/base/rng.h"
#include "quiver/agents/runtime/process/subprocess.h"

namespace quiver::tools {
namespace {

using agents::Subprocess;

using agents::DdsReplica;
using agents::monotonic_ns;
using graph::NodeId;
using graph::Symbol;
using graph::Value;
using json = nlohmann::json;

constexpr std::int64_t kSec = 1'000'000'000;

std::string self_exe() {
  char buf[4096];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "quiver";
}

std::unique_ptr<DdsReplica> make_agent(const std::string& name, const DdsFlags& dds) {
  agents::DdsReplicaOptions o;
  o.name = name;
  o.dds.max_blocking_ns = 2 * kSec;  // a benchmark wants back-pressure, not drops
  auto a = dds.create_agent(o);
  if (!a.ok()) {
    agents::named_logger(name)->error("{}", a.error().to_string());
    std::exit(2);
  }
  return std::move(*a);
}

/// Waits until every live peer holds all this agent has written.
bool wait_all_hold(DdsReplica& a, std::int64_t timeout_ns) {
  const std::uint64_t seq = a.replicator().last_seq();
  return a.spin_until([&] { return a.replicator().all_peers_hold(a.id(), seq); }, timeout_ns);
}

/// The writer tells the readers which phase of the benchmark it is in.
void set_phase(graph::Graph& g, NodeId control, const char* phase) {
  auto tx = g.begin();
  (void)tx.set(control, Symbol("phase"), Value(phase));
  (void)tx.commit();
}

struct RoleFlags {
  std::string role;
  DdsFlags dds;
  int id = 0;
  int readers = 1;
  long updates = 1'000'000;
  int batch = 100;
  int latency_samples = 2000;
  int join_nodes = 10000;
  int agents = 20;
  double seconds = 5;
  bool with_viewer = false;
  bool viewer_every_delta = false;
  bool secure = false;  ///< make a temporary key directory for the roles (docs/security.md)
  bool secure_transport = false;  ///< the same, DDS Security only: no signed deltas, no permissions
};

// ------------------------------------------------------------------ throughput / latency / join

void writer_role(const RoleFlags& f) {
  auto agent = make_agent("bench-writer", f.dds);
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  if (!a.spin_until([&] { return a.replicator().live_peer_count() >= static_cast<std::size_t>(f.readers); }, 30 * kSec)) {
    agents::named_logger("bench writer")->error("only {} of {} readers appeared", a.replicator().live_peer_count(), f.readers);
    std::exit(1);
  }
  std::vector<Symbol> attrs;
  for (int k = 0; k < 10; ++k) attrs.emplace_back("a" + std::to_string(k));
  std::vector<NodeId> ids;
  NodeId control, probe;
  auto add_nodes = [&](int from, int to) {
    auto tx = g.begin();
    for (int i = from; i < to; ++i) {
      std::vector<std::pair<Symbol, Value>> init;
      for (Symbol s : attrs) init.emplace_back(s, Value(0.0));
      ids.push_back(*tx.create_node("object", "n" + std::to_string(i), std::move(init)));
    }
    (void)tx.commit();
  };
  {
    auto tx = g.begin();
    control = *tx.create_node("bench", "bench-control", {{Symbol("phase"), Value("seed")}});
    probe = *tx.create_node("bench", "bench-probe", {{Symbol("t"), Value(std::int64_t{0})}});
    (void)tx.commit();
  }
  for (int i = 0; i < 1000; i += 250) add_nodes(i, i + 250);
  if (!wait_all_hold(a, 30 * kSec))
    agents::named_logger("bench writer")->warn("readers did not confirm the seed");

  // Throughput: N random writes in transactions of `batch`.
  Rng rng(1);
  const std::int64_t t0 = monotonic_ns();
  long done = 0, txns = 0;
  while (done < f.updates) {
    auto tx = g.begin();
    long n = std::min<long>(f.batch, f.updates - done);
    for (long i = 0; i < n; ++i) (void)tx.set(ids[rng.below(1000)], attrs[rng.below(10)], Value(rng.uniform()));
    (void)tx.commit();
    done += n;
    if (++txns % 16 == 0) a.spin_once(0);  // keep up with summaries and pulls
  }
  const std::int64_t t_local = monotonic_ns();
  set_phase(g, control, "throughput-done");
  if (!wait_all_hold(a, 60 * kSec))
    agents::named_logger("bench writer")->warn("readers did not confirm the throughput phase");

  // Latency: single unbatched writes, spaced so they do not queue behind each other.
  set_phase(g, control, "latency");
  a.spin_for(100'000'000);
  for (int i = 0; i < f.latency_samples; ++i) {
    auto tx = g.begin();
    (void)tx.set(probe, Symbol("t"), Value(monotonic_ns()));
    (void)tx.commit();
    a.spin_for(1'000'000);
  }
  a.spin_for(200'000'000);

  // Join: grow to `join_nodes` nodes x 10 attributes, then a late joiner syncs from the replicas.
  for (int i = 1000; i < f.join_nodes; i += 500) add_nodes(i, std::min(i + 500, f.join_nodes));
  set_phase(g, control, "join");
  if (!wait_all_hold(a, 60 * kSec))
    agents::named_logger("bench writer")->warn("readers did not confirm the join graph");
  json ready;
  ready["role"] = "writer";
  ready["phase"] = "ready-for-joiner";
  ready["t0_ns"] = t0;
  ready["t_local_done_ns"] = t_local;
  ready["write_timeouts"] = a.transport().stats().write_timeouts;
  std::cout << ready.dump() << std::endl;
  // Wait for the joiner (one more peer) to hold everything, then end the run.
  a.spin_until([&] { return a.replicator().live_peer_count() > static_cast<std::size_t>(f.readers); }, 60 * kSec);
  wait_all_hold(a, 60 * kSec);
  set_phase(g, control, "done");
  a.spin_for(300'000'000);
}

void reader_role(const RoleFlags& f) {
  auto agent = make_agent("bench-reader-" + std::to_string(f.id), f.dds);
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  std::vector<double> latencies_us;
  std::string phase;
  std::int64_t t_throughput_done = 0;
  const Symbol kPhase("phase"), kT("t");
  g.subscribe([&](const graph::ChangeBatch& b) {
    const std::int64_t now = monotonic_ns();
    for (const auto& n : b.nodes) {
      if (n.kind != graph::ChangeKind::kUpdated) continue;
      for (Symbol s : n.attrs) {
        if (s == kT && phase == "latency") {
          if (const auto* v = g.attr(n.id, kT)->get_if<std::int64_t>()) latencies_us.push_back((now - *v) / 1000.0);
        } else if (s == kPhase) {
          phase = *g.attr(n.id, kPhase)->get_if<std::string>();
          if (phase == "throughput-done") t_throughput_done = now;
        }
      }
    }
  });
  a.spin_until([&] { return phase == "done"; }, 600 * kSec);
  json out;
  out["role"] = "reader";
  out["id"] = f.id;
  out["t_throughput_done_ns"] = t_throughput_done;
  out["latencies_us"] = latencies_us;
  out["deltas_applied"] = a.replicator().stats().deltas_applied;
  out["states_applied"] = a.replicator().stats().states_applied;
  std::cout << out.dump() << std::endl;
}

void joiner_role(const RoleFlags& f) {
  const std::int64_t t_start = monotonic_ns();
  auto agent = make_agent("bench-joiner", f.dds);
  DdsReplica& a = *agent;
  const std::int64_t t_created = monotonic_ns();
  const std::size_t want = static_cast<std::size_t>(f.join_nodes) + 2;
  bool ok = a.spin_until([&] { return a.graph().node_count() >= want && a.replicator().synced(); }, 60 * kSec);
  const std::int64_t t_synced = monotonic_ns();
  json out;
  out["role"] = "joiner";
  out["synced"] = ok;
  out["nodes"] = a.graph().node_count();
  out["join_ms"] = (t_synced - t_created) / 1e6;
  out["join_ms_from_process_start"] = (t_synced - t_start) / 1e6;
  out["states_applied"] = a.replicator().stats().states_applied;
  out["state_bytes"] = a.replicator().stats().state_bytes_received;
  std::cout << out.dump() << std::endl;
  a.spin_for(500'000'000);
}

// ------------------------------------------------------------------ human tracking (AGM paper)

constexpr int kPeople = 2, kJoints = 15, kHz = 30;

void tracker_role(const RoleFlags& f) {
  auto agent = make_agent("tracker", f.dds);
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  std::vector<std::vector<NodeId>> joints(kPeople);
  std::vector<NodeId> people;
  {
    auto tx = g.begin();
    NodeId world = *tx.create_node("world", "world");
    for (int p = 0; p < kPeople; ++p) {
      NodeId person = *tx.create_node("person", "person" + std::to_string(p));
      people.push_back(person);
      (void)tx.set_rt(world, person, graph::Pose{}, 0);
      for (int j = 0; j < kJoints; ++j) {
        joints[p].push_back(*tx.create_node("joint", "person" + std::to_string(p) + "_joint" + std::to_string(j)));
        (void)tx.set_rt(person, joints[p].back(), graph::Pose{}, 0);
      }
    }
    (void)tx.commit();
  }
  const std::size_t listeners = static_cast<std::size_t>(f.agents - 1);
  a.spin_until([&] { return a.replicator().live_peer_count() >= listeners; }, 60 * kSec);
  wait_all_hold(a, 60 * kSec);
  // 2 people x 15 joints at 30 Hz: one transaction per person per frame.
  const std::int64_t period = kSec / kHz;
  std::int64_t next = monotonic_ns();
  const std::int64_t end = next + static_cast<std::int64_t>(f.seconds * kSec);
  long updates = 0;
  int frame = 0;
  while (monotonic_ns() < end) {
    for (int p = 0; p < kPeople; ++p) {
      auto tx = g.begin();
      const std::int64_t stamp = monotonic_ns();
      for (int j = 0; j < kJoints; ++j) {
        graph::Pose pose;
        pose.translation = {0.1 * j, 0.01 * frame, 1.0};
        (void)tx.set_rt(people[p], joints[p][j], pose, stamp);
        ++updates;
      }
      (void)tx.commit();
    }
    ++frame;
    next += period;
    while (monotonic_ns() < next) a.spin_once(next - monotonic_ns());
  }
  {
    auto tx = g.begin();
    (void)tx.create_node("bench", "tracking-done");
    (void)tx.commit();
  }
  a.spin_for(500'000'000);
  json out;
  out["role"] = "tracker";
  out["updates"] = updates;
  out["seconds"] = f.seconds;
  std::cout << out.dump() << std::endl;
}

void listener_role(const RoleFlags& f) {
  auto agent = make_agent("listener-" + std::to_string(f.id), f.dds);
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  std::vector<double> latencies_us;
  bool done = false;
  g.subscribe([&](const graph::ChangeBatch& b) {
    const std::int64_t now = monotonic_ns();
    for (const auto& e : b.edges) {
      if (e.kind != graph::ChangeKind::kUpdated || !(e.key.type == graph::symbols::rt())) continue;
      if (auto rt = g.rt_edge(e.key.to); rt && rt->stamp > 0) latencies_us.push_back((now - rt->stamp) / 1000.0);
    }
    for (const auto& n : b.nodes)
      if (n.kind == graph::ChangeKind::kCreated && g.name_of(n.id) == "tracking-done") done = true;
  });
  a.spin_until([&] { return done; }, static_cast<std::int64_t>((f.seconds + 120) * kSec));
  json out;
  out["role"] = "listener";
  out["id"] = f.id;
  out["latencies_us"] = latencies_us;
  std::cout << out.dump() << std::endl;
}

// ------------------------------------------------------------------ coordinators

std::vector<std::string> role_argv(const std::string& role, const DdsFlags& dds, std::vector<std::string> extra) {
  std::vector<std::string> argv = {self_exe(), "bench-dds-role", role, "--domain", std::to_string(dds.domain),
                                   "--dds-config", dds.dds_config, "--loss-permille", std::to_string(dds.loss_permille)};
  if (!dds.security.empty()) argv.insert(argv.end(), {"--security", dds.security});
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

/// `n` processes of one role, numbered by --id.
std::optional<std::vector<Subprocess>> spawn_roles(const std::string& role, int n,
                                                   const DdsFlags& dds,
                                                   const std::vector<std::string>& common) {
  std::vector<Subprocess> out;
  for (int i = 0; i < n; ++i) {
    auto extra = common;
    extra.insert(extra.end(), {"--id", std::to_string(i)});
    auto p = Subprocess::spawn(role_argv(role, dds, extra));
    if (!p) return std::nullopt;
    out.push_back(std::move(*p));
  }
  return out;
}

std::optional<json> read_json(Subprocess& p, const char* who, int timeout_ms) {
  for (;;) {
    auto line = p.read_line(timeout_ms);
    if (!line) {
      agents::named_logger("quiver bench dds")->error("no result from the {} process", who);
      return std::nullopt;
    }
    auto j = json::parse(*line, nullptr, false);
    if (!j.is_discarded() && j.is_object()) return j;
  }
}

// `quiver view` on the benchmark's domain with a page's event stream open (read by a thread of
// this process), so the viewer does all its work while the writer writes.
class AttachedViewer {
 public:
  static std::unique_ptr<AttachedViewer> start(const DdsFlags& dds, bool every_delta) {
    std::vector<std::string> argv = {self_exe(), "--log-level", "warn", "view", "--domain", std::to_string(dds.domain),
                                     "--dds-config", dds.dds_config, "--listen", "127.0.0.1:0"};
    if (every_delta) argv.push_back("--every-delta");
    auto p = Subprocess::spawn(argv);
    if (!p) return nullptr;
    auto line = p->read_line(20'000);
    const auto at = line ? line->find("http://127.0.0.1:") : std::string::npos;
    if (at == std::string::npos) {
      agents::named_logger("quiver bench dds")->error("quiver view did not start");
      return nullptr;
    }
    auto v = std::make_unique<AttachedViewer>();
    v->process_ = std::make_unique<Subprocess>(std::move(*p));
    v->state_ = std::make_shared<State>();
    const int port = std::stoi(line->substr(at + 17));
    v->reader_ = std::thread([state = v->state_, port] {
      httplib::Client c("127.0.0.1", port);
      c.set_read_timeout(1, 0);
      while (!state->stop.load())
        (void)c.Get("/api/events", [&](const char*, std::size_t n) {
          state->bytes += n;
          return !state->stop.load();
        });
    });
    // Measured attached, not starting: the viewer joins, loads the graph and opens its page
    // before the writers begin (its start-up is a one-off, not a cost per change).
    std::this_thread::sleep_for(std::chrono::seconds(2));
    return v;
  }
  AttachedViewer() = default;
  AttachedViewer(const AttachedViewer&) = delete;
  AttachedViewer& operator=(const AttachedViewer&) = delete;
  ~AttachedViewer() { (void)stop(); }
  /// Stops the viewer; @returns the event bytes the page received.
  std::uint64_t stop() {
    if (state_) state_->stop.store(true);
    if (reader_.joinable()) reader_.join();
    if (process_) {
      ::kill(process_->pid(), SIGTERM);
      process_->wait(10'000);
      process_.reset();
    }
    return state_ ? state_->bytes.load() : 0;
  }

 private:
  struct State {
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> bytes{0};
  };
  std::unique_ptr<Subprocess> process_;
  std::shared_ptr<State> state_;
  std::thread reader_;
};

// --secure: a fresh CA and one identity per role, in a temporary directory removed at exit.
std::optional<std::string> make_bench_keys(const RoleFlags& f) {
  char tmpl[] = "/tmp/quiver-bench-keys-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return std::nullopt;
  const std::string dir = tmpl;
  std::vector<std::string> names = {"bench-writer", "bench-joiner"};
  for (int i = 0; i < f.readers; ++i) names.push_back("bench-reader-" + std::to_string(i));
  Status s = agents::security::init_keys(dir);
  for (const auto& n : names)
    if (s.ok()) s = agents::security::add_agent(dir, n);
  if (!s.ok()) {
    agents::named_logger("bench")->error("--secure: {}", s.error().to_string());
    return std::nullopt;
  }
  return dir;
}

int run_bench_dds(const RoleFlags& flags) {
  RoleFlags f = flags;
  std::shared_ptr<void> cleanup;
  if (f.secure || f.secure_transport) {
    if (f.with_viewer) {
      agents::named_logger("bench")->error("--secure with --with-viewer is not supported");
      return 2;
    }
    auto dir = make_bench_keys(f);
    if (!dir) return 2;
    f.dds.security = *dir;
    cleanup = std::shared_ptr<void>(nullptr, [d = *dir](void*) { std::filesystem::remove_all(d); });
  }
  std::vector<std::string> common = {"--updates", std::to_string(f.updates), "--batch", std::to_string(f.batch),
                                     "--readers", std::to_string(f.readers), "--latency-samples",
                                     std::to_string(f.latency_samples), "--join-nodes", std::to_string(f.join_nodes)};
  if (f.secure_transport) common.push_back("--transport-only");
  auto readers = spawn_roles("reader", f.readers, f.dds, common);
  if (!readers) return 2;
  std::unique_ptr<AttachedViewer> viewer;
  if (f.with_viewer) {
    viewer = AttachedViewer::start(f.dds, f.viewer_every_delta);
    if (!viewer) return 2;
  }
  auto writer = Subprocess::spawn(role_argv("writer", f.dds, common));
  if (!writer) return 2;
  auto ready = read_json(*writer, "writer", 600'000);
  if (!ready) return 1;
  auto joiner = Subprocess::spawn(role_argv("joiner", f.dds, common));
  if (!joiner) return 2;
  auto joined = read_json(*joiner, "joiner", 120'000);
  std::int64_t t_done = 0;
  std::vector<double> lat;
  for (int i = 0; i < f.readers; ++i) {
    auto r = read_json((*readers)[i], "reader", 120'000);
    if (!r) return 1;
    t_done = std::max<std::int64_t>(t_done, (*r)["t_throughput_done_ns"].get<std::int64_t>());
    for (double v : (*r)["latencies_us"]) lat.push_back(v);
  }
  writer->wait(10'000);
  for (auto& r : *readers) r.wait(10'000);
  joiner->wait(10'000);
  const double secs = static_cast<double>(t_done - (*ready)["t0_ns"].get<std::int64_t>()) / 1e9;
  json out;
  out["bench"] = "dds";
  out["security"] = f.secure ? "dds+signed-deltas" : f.secure_transport ? "dds" : "none";
  out["updates"] = f.updates;
  out["batch"] = f.batch;
  out["readers"] = f.readers;
  out["updates_per_s"] = static_cast<long>(static_cast<double>(f.updates) / secs);
  const Percentiles pct(lat);
  out["latency_us_p50"] = round_to(pct.at(0.50), 1);
  out["latency_us_p99"] = round_to(pct.at(0.99), 1);
  out["latency_samples"] = lat.size();
  out["join_ms_10k"] = joined ? (*joined)["join_ms"] : json(nullptr);
  if (joined) out["join_ms_10k_from_process_start"] = (*joined)["join_ms_from_process_start"];
  out["write_timeouts"] = (*ready)["write_timeouts"];
  out["with_viewer"] = f.with_viewer;
  if (f.with_viewer) out["viewer_every_delta"] = f.viewer_every_delta;
  if (viewer) out["viewer_event_bytes"] = viewer->stop();
  std::cout << out.dump() << std::endl;
  return joined && (*joined)["synced"].get<bool>() ? 0 : 1;
}

int run_bench_tracking(const RoleFlags& f) {
  std::vector<std::string> common = {"--agents", std::to_string(f.agents), "--seconds", std::to_string(f.seconds)};
  auto listeners = spawn_roles("listener", f.agents - 1, f.dds, common);
  if (!listeners) return 2;
  std::unique_ptr<AttachedViewer> viewer;
  if (f.with_viewer && !(viewer = AttachedViewer::start(f.dds, f.viewer_every_delta))) return 2;
  auto tracker = Subprocess::spawn(role_argv("tracker", f.dds, common));
  if (!tracker) return 2;
  auto t = read_json(*tracker, "tracker", static_cast<int>((f.seconds + 120) * 1000));
  if (!t) return 1;
  std::vector<double> lat;
  for (auto& l : *listeners) {
    auto r = read_json(l, "listener", 30'000);
    if (!r) return 1;
    for (double v : (*r)["latencies_us"]) lat.push_back(v);
  }
  json out;
  out["bench"] = "dds-tracking";
  out["agents"] = f.agents;
  out["rt_updates_per_s"] = static_cast<long>((*t)["updates"].get<long>() / f.seconds);
  out["deliveries"] = lat.size();
  const Percentiles pct(lat);
  out["latency_us_p50"] = round_to(pct.at(0.50), 1);
  out["latency_us_p99"] = round_to(pct.at(0.99), 1);
  out["latency_us_max"] = round_to(pct.at(1.0), 1);
  out["with_viewer"] = f.with_viewer;
  if (f.with_viewer) out["viewer_every_delta"] = f.viewer_every_delta;
  if (viewer) out["viewer_event_bytes"] = viewer->stop();
  std::cout << out.dump() << std::endl;
  return 0;
}

}  // namespace

void add_dds_bench_commands(CLI::App& app) {
  auto f = std::make_shared<RoleFlags>();
  f->dds.domain = 77;
  CLI::App* bench = app.get_subcommand("bench");
  auto* dds = bench->add_subcommand("dds", "DDS transport: one writer and K reader processes on loopback");
  f->dds.add_to(dds);
  dds->add_option("--updates", f->updates)->check(CLI::Range(1L, 1'000'000'000L))->capture_default_str();
  dds->add_option("--batch", f->batch)->check(CLI::Range(1, 100000))->capture_default_str();
  dds->add_option("--readers", f->readers)->check(CLI::Range(1, 64))->capture_default_str();
  dds->add_option("--latency-samples", f->latency_samples)->check(CLI::Range(0, 10'000'000))->capture_default_str();
  dds->add_option("--join-nodes", f->join_nodes)->check(CLI::Range(0, 10'000'000))->capture_default_str();
  dds->add_flag("--with-viewer", f->with_viewer,
                "run `quiver view` on the domain, with a page's event stream open, during the benchmark");
  dds->add_flag("--viewer-every-delta", f->viewer_every_delta, "the viewer reads every delta (`quiver view --every-delta`)");
  dds->add_flag("--secure", f->secure,
                "DDS Security and signed, policy-checked deltas: every role gets an identity from a fresh CA in a "
                "temporary directory (docs/security.md)");
  dds->add_flag("--secure-transport", f->secure_transport,
                "DDS Security alone, as --secure but without signed deltas and graph-level permissions: what each "
                "layer costs");
  dds->callback([f] { set_exit_code(run_bench_dds(*f)); });

  auto* tr = bench->add_subcommand("dds-tracking",
                                   "DDS transport: the AGM human-tracking load (2 people x 15 joints x 30 Hz) to N-1 agents");
  f->dds.add_to(tr);
  tr->add_option("--agents", f->agents)->check(CLI::Range(2, 100))->capture_default_str();
  tr->add_option("--seconds", f->seconds)->check(CLI::Range(0.1, 3600.0))->capture_default_str();
  tr->add_flag("--with-viewer", f->with_viewer, "run `quiver view` on the domain, with a page's event stream open");
  tr->add_flag("--viewer-every-delta", f->viewer_every_delta, "the viewer reads every delta (`quiver view --every-delta`)");
  tr->callback([f] { set_exit_code(run_bench_tracking(*f)); });

  auto r = std::make_shared<RoleFlags>();
  auto* role = app.add_subcommand("bench-dds-role", "internal: one process of a DDS benchmark");
  role->group("");  // hidden
  role->add_option("role", r->role)->required();
  r->dds.add_to(role);
  role->add_option("--id", r->id)->check(CLI::Range(0, 1000));
  role->add_option("--readers", r->readers)->check(CLI::Range(1, 64));
  role->add_option("--updates", r->updates)->check(CLI::Range(1L, 1'000'000'000L));
  role->add_option("--batch", r->batch)->check(CLI::Range(1, 100000));
  role->add_option("--latency-samples", r->latency_samples)->check(CLI::Range(0, 10'000'000));
  role->add_option("--join-nodes", r->join_nodes)->check(CLI::Range(0, 10'000'000));
  role->add_option("--agents", r->agents)->check(CLI::Range(2, 100));
  role->add_option("--seconds", r->seconds)->check(CLI::Range(0.1, 3600.0));
  role->add_flag("--transport-only", r->secure_transport);
  role->callback([r] {
    if (r->secure_transport) r->dds.graph_security = false;
    if (r->role == "writer") writer_role(*r);
    else if (r->role == "reader") reader_role(*r);
    else if (r->role == "joiner") joiner_role(*r);
    else if (r->role == "tracker") tracker_role(*r);
    else if (r->role == "listener") listener_role(*r);
    else set_exit_code(2);
  });
}

}  // namespace quiver::tools
