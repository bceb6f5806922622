// quiver view: the live viewer (a page on 127.0.0.1); quiver record: a .qrec file of what a
// replica receives. Both join as observers, or view a recording or a world file.

#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>

#include "commands.h"
#include "dds_options.h"
#include "observer.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/rules/schema/schema.h"
#include "quiver/agents/view/recording/graph_recorder.h"
#include "quiver/agents/view/recording/record_file.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/view/viewer/viewer.h"
#include "quiver/graph/world_file.h"

namespace quiver::tools {
namespace {

using agents::DdsReplica;
using nlohmann::json;

std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int) { g_stop.store(true); }
void catch_stop_signals() {
  g_stop.store(false);
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

struct ViewFlags {
  DdsFlags dds;
  std::string listen = "127.0.0.1:8080";
  std::string replay, world, grammar, assets;
  double run_for_s = 0;
  double history_mb = 64;
  int nice = 10;
  double sample_ms = 50;
  double sample_kb_per_s = 256;
  bool every_delta = false;
};

Result<std::pair<std::string, int>> parse_listen(const std::string& s) {
  const auto colon = s.rfind(':');
  if (colon == std::string::npos || colon == 0)
    return make_error(ErrorCode::kInvalidArgument,
                      "--listen '" + s + "': expected HOST:PORT, e.g. 127.0.0.1:8080");
  const std::string port = s.substr(colon + 1);
  if (port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) > 65535)
    return make_error(ErrorCode::kInvalidArgument,
                      "--listen '" + s + "': the port must be 0..65535");
  return std::pair{s.substr(0, colon), std::stoi(port)};
}

// This domain's replicas, then the other robots' agents its gateways list (docs/teams.md): each
// with the robot it runs on ("" outside a team). The robots listed alive are the reachable ones.
json agents_json(agents::Replicator& r) {
  json out = json::array();
  out.push_back({{"name", r.options().name},
                 {"id", r.graph().replica().to_string()},
                 {"robot", r.robot_here()},
                 {"observer", true},
                 {"alive", true},
                 {"self", true}});
  for (const agents::PeerInfo& p : r.peers())
    out.push_back({{"name", p.name},
                   {"id", p.id.to_string()},
                   {"robot", r.robot_of(p.id)},
                   {"observer", p.observer},
                   {"gateway", p.gateway},
                   {"alive", p.alive},
                   {"self", false}});
  for (const agents::Member& m : r.remote_members())
    out.push_back({{"name", m.name},
                   {"id", m.id.to_string()},
                   {"robot", m.robot},
                   {"via", r.name_of(m.via)},
                   {"remote", true},
                   {"observer", false},
                   {"alive", true},
                   {"self", false}});
  return out;
}

// A change's writer as the viewer shows it: the agent, and in a team the robot it runs on.
std::string writer_of(const agents::Replicator& r, const graph::ReplicaId& id) {
  const std::string robot = r.robot_of(id);
  return robot.empty() ? r.name_of(id) : r.name_of(id) + " @ " + robot;
}

// Runs `tick` every few ms until SIGINT/SIGTERM or `run_for_s`.
void serve_until_stopped(double run_for_s, const std::function<void()>& wait_a_little) {
  const std::int64_t end = run_for_s > 0
                               ? agents::monotonic_ns() + static_cast<std::int64_t>(run_for_s * 1e9)
                               : INT64_MAX;
  while (!g_stop.load() && agents::monotonic_ns() < end) wait_a_little();
}

int view_static(const ViewFlags& f, agents::viewer::ViewerOptions vo) {
  auto log = agents::named_logger("quiver view");
  graph::Graph g(agents::recording::replay_replica_id());
  std::mutex mu;
  std::int64_t now = 0;
  std::string origin;
  std::map<graph::ReplicaId, std::string> names;
  agents::viewer::Hooks hooks;
  hooks.run_on_owner = [&](const std::function<void()>& fn) {
    std::lock_guard l(mu);
    fn();
  };
  hooks.clock = [&] { return now; };
  hooks.name_of = [&](const graph::ReplicaId& r) {
    auto it = names.find(r);
    return it != names.end() ? it->second : r.to_string();
  };
  auto viewer = agents::viewer::Viewer::start(g, vo, hooks);
  if (!viewer.ok()) {
    log->error("{}", viewer.error().message);
    return 2;
  }
  {
    std::lock_guard l(mu);
    if (!f.replay.empty()) {
      auto rec = agents::recording::read_recording(f.replay);
      if (!rec.ok()) {
        log->error("{}", rec.error().message);
        return 2;
      }
      if (!rec->note.empty()) log->warn("{}: {}", f.replay, rec->note);
      for (const auto& fr : rec->changes) {
        now = fr.t_ns;
        if (!fr.origin.empty()) names[fr.delta.origin] = fr.origin;
        g.merge(fr.delta);
      }
      log->info("{}: {} frames, {:.1f} s; {} nodes, {} edges at the end", f.replay,
                rec->changes.size(),
                rec->changes.empty() ? 0.0 : static_cast<double>(rec->changes.back().t_ns) / 1e9,
                g.node_count(), g.edge_count());
    } else {
      auto seed = graph::world_seed_file(f.world);
      if (!seed.ok()) {
        log->error("{}", seed.error().message);
        return 2;
      }
      names[seed->delta.origin] = "world file";
      g.merge(seed->delta);
    }
    (*viewer)->tick(INT64_MAX / 2);
  }
  std::cout << "quiver view: " << (*viewer)->url() << "  (" << vo.title << ")" << std::endl;
  serve_until_stopped(f.run_for_s, [] { ::usleep(50'000); });
  return 0;
}

// CPU time of this process, all threads (ns).
std::int64_t process_cpu_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int run_view(const ViewFlags& f) {
  auto log = agents::named_logger("quiver view");
  auto listen = parse_listen(f.listen);
  if (!listen.ok()) {
    log->error("{}", listen.error().message);
    return 2;
  }
  agents::viewer::ViewerOptions vo;
  vo.host = listen->first;
  vo.port = listen->second;
  vo.assets_dir = f.assets;
  vo.history_bytes = static_cast<std::uint64_t>(f.history_mb * (1 << 20));
  if (!f.dds.schema.empty()) {  // the page shows it; a live viewer's replica also enforces it
    auto s = agents::schema::Schema::load(f.dds.schema);
    if (!s.ok()) {
      log->error("{}", s.error().message);
      return 2;
    }
    vo.schema = nlohmann::json::parse(s->to_json());
  }
  catch_stop_signals();
  if (!f.replay.empty() || !f.world.empty()) {
    vo.mode = f.replay.empty() ? "world" : "replay";
    vo.title = f.replay.empty() ? f.world : f.replay;
    return view_static(f, vo);
  }
  // An observer yields the processor to the agents it watches (docs/viewer.md).
  if (f.nice != 0 && ::setpriority(PRIO_PROCESS, 0, f.nice) != 0)
    log->warn("could not lower the viewer's priority to nice {}: {}", f.nice, std::strerror(errno));
  // By default the viewer samples: it reads no deltas (writers pay nothing per change for it) and
  // pulls what changed 20 times a second, or less often when what changed is more than
  // --sample-kb-per-s (a busy graph: then the writers do not serialise more for it). --every-delta
  // reads each delta, best effort.
  ObserverMode mode{.best_effort = true,
                    .sample_ns = f.every_delta ? 0 : static_cast<std::int64_t>(f.sample_ms * 1e6),
                    .sample_bytes_per_s = static_cast<std::size_t>(f.sample_kb_per_s * 1024)};
  auto created = open_observer(f.dds, "quiver-view", mode);
  if (!created.ok()) {
    log->error("{}", created.error().to_string());
    return 2;
  }
  DdsReplica& a = **created;
  agents::LockManager locks(a.graph(), &a.replicator(), agents::monotonic_ns);
  std::unique_ptr<agents::GrammarGuard> guard;
  if (!f.grammar.empty()) {
    auto gr = agents::load_grammar_file(f.grammar);
    if (!gr.ok()) {
      log->error("{}", gr.error().message);
      return 2;
    }
    guard = std::make_unique<agents::GrammarGuard>(
        a.graph(), agents::GrammarChecker(std::move(gr.value())), "quiver-view");
  }
  const std::int64_t start = agents::monotonic_ns();
  agents::viewer::Hooks hooks;
  hooks.run_on_owner = [&a](const std::function<void()>& fn) { a.call(fn).get(); };
  hooks.clock = [start] { return agents::monotonic_ns() - start; };
  hooks.name_of = [&a](const graph::ReplicaId& r) { return writer_of(a.replicator(), r); };
  hooks.agents = [&a] { return agents_json(a.replicator()); };
  hooks.decorate = [&](agents::viewer::Decor& d) {
    for (const auto& [root, w] : locks.winners())
      d.locks[root] = {a.replicator().name_of(w.holder), w.epoch, w.priority};
    if (guard)
      for (const auto& v : guard->open()) d.violations.push_back(v);
  };
  vo.mode = "live";
  vo.title = "DDS domain " + std::to_string(f.dds.domain);
  auto viewer = agents::viewer::Viewer::start(a.graph(), vo, hooks);
  if (!viewer.ok()) {
    log->error("{}", viewer.error().message);
    return 2;
  }
  std::cout << "quiver view: " << (*viewer)->url() << "  (" << vo.title << ")" << std::endl;
  a.every(5'000'000, [&] { (*viewer)->tick(agents::monotonic_ns()); });
  // A twentieth of a core at most: when the viewer's whole process (pulls, merges, pushes,
  // Cyclone's threads) used more over the last quarter second, it pulls half as often (down to
  // once a second); under half of that, twice as often again (up to --sample-ms).
  if (mode.sample_ns > 0) {
    auto last = std::make_shared<std::pair<std::int64_t, std::int64_t>>(agents::monotonic_ns(), process_cpu_ns());
    a.every(250'000'000, [&a, last, base = mode.sample_ns] {
      const std::int64_t now = agents::monotonic_ns(), cpu = process_cpu_ns();
      const double share = static_cast<double>(cpu - last->second) / static_cast<double>(std::max<std::int64_t>(1, now - last->first));
      *last = {now, cpu};
      const std::int64_t period = a.replicator().options().sample_ns;
      if (share > 0.05) a.replicator().set_sample_ns(std::min<std::int64_t>(period * 2, 1'000'000'000));
      else if (share < 0.025) a.replicator().set_sample_ns(std::max(period / 2, base));
    });
  }
  a.every(200'000'000, [&] { locks.tick(); });
  serve_until_stopped(f.run_for_s, [&] { a.spin_once(20'000'000); });
  viewer->reset();
  return 0;
}

struct RecordFlags {
  DdsFlags dds;
  std::string out;
  double max_mb = 256;
  double run_for_s = 0;
};

int run_record(const RecordFlags& f) {
  auto log = agents::named_logger("quiver record");
  auto created = open_observer(f.dds, "quiver-record", ObserverMode{.best_effort = true});
  if (!created.ok()) {
    log->error("{}", created.error().to_string());
    return 2;
  }
  DdsReplica& a = **created;
  auto writer = agents::recording::RecordWriter::create(
      f.out, {.max_bytes = static_cast<std::uint64_t>(f.max_mb * (1 << 20)),
              .start_wall_ns = static_cast<std::uint64_t>(
                  std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count())});
  if (!writer.ok()) {
    log->error("{}", writer.error().message);
    return 2;
  }
  catch_stop_signals();
  const std::int64_t start = agents::monotonic_ns();
  Status failed;
  agents::recording::GraphRecorder rec(
      a.graph(), [start] { return agents::monotonic_ns() - start; },
      [&a](const graph::ReplicaId& r) { return a.replicator().name_of(r); },
      [&](agents::recording::RecordedChange&& fr) {
        if (!failed.ok()) return;
        failed = (*writer)->append(fr, [&a] { return a.graph().state(); });
        if (!failed.ok()) g_stop.store(true);
      });
  a.every(500'000'000, [&] { (void)(*writer)->flush(); });
  std::cout << "quiver record: recording DDS domain " << f.dds.domain << " into " << f.out
            << std::endl;
  serve_until_stopped(f.run_for_s, [&] { a.spin_once(20'000'000); });
  Status flushed = (*writer)->flush();
  if (!failed.ok() || !flushed.ok()) {
    log->error("{}", (!failed.ok() ? failed : flushed).error().message);
    return 1;
  }
  std::cout << "quiver record: " << (*writer)->changes_written() << " frames, " << (*writer)->bytes()
            << " bytes in " << f.out
            << ((*writer)->rotations() > 0 ? " (older part in " + f.out + ".1)" : std::string())
            << std::endl;
  return 0;
}

}  // namespace

void add_view_commands(CLI::App& app) {
  auto vf = std::make_shared<ViewFlags>();
  auto* view = app.add_subcommand(
      "view", "Serve a live page of the world model (graph, 3D tree, inspector, timeline)");
  vf->dds.add_to(view);
  view->add_option("--listen", vf->listen,
                   "HOST:PORT to serve on (default 127.0.0.1:8080; port 0: any free one)");
  auto* replay =
      view->add_option("--replay", vf->replay, "show a recording (.qrec) instead of a live domain")
          ->check(CLI::ExistingFile);
  view->add_option("--world", vf->world, "show a world file instead of a live domain")
      ->check(CLI::ExistingFile)
      ->excludes(replay);
  view->add_option("--grammar", vf->grammar,
                   "highlight the violations of this grammar's constraints")
      ->check(CLI::ExistingFile);
  view->add_option("--assets", vf->assets, "the page's files (default: installed with Quiver)");
  view->add_option("--history-mb", vf->history_mb,
                   "memory for the timeline (oldest frames fold into a base state)")
      ->check(CLI::Range(1.0, 65536.0));
  view->add_option(
          "--nice", vf->nice,
          "live: run at this scheduling niceness, so that the agents come first (0: as started)")
      ->check(CLI::Range(0, 19))
      ->capture_default_str();
  auto* every = view->add_flag("--every-delta", vf->every_delta,
                               "live: read every delta (a timeline frame per change, each with its author); writers "
                               "then send this viewer each change (default: pull what changed, --sample-ms)");
  view->add_option("--sample-ms", vf->sample_ms, "live: how often to pull what changed, in ms")
      ->check(CLI::Range(5.0, 10000.0))
      ->capture_default_str()
      ->excludes(every);
  view->add_option("--sample-kb-per-s", vf->sample_kb_per_s,
                   "live: the most it asks its peers to send per second, in KiB; a busy graph is then sampled less "
                   "often")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str()
      ->excludes(every);
  view->add_option("--for", vf->run_for_s, "stop after this many seconds (default: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e7));
  view->callback([vf] { set_exit_code(run_view(*vf)); });

  auto rf = std::make_shared<RecordFlags>();
  auto* record = app.add_subcommand(
      "record",
      "Record every change a DDS domain's agents make, with origin and time, into a .qrec file");
  rf->dds.add_to(record);
  record->add_option("-o,--output", rf->out, "the recording file (.qrec)")->required();
  record
      ->add_option("--max-mb", rf->max_mb,
                   "the file and its older part PATH.1 stay under this many MiB together")
      ->check(CLI::Range(0.01, 1e6));
  record->add_option("--for", rf->run_for_s, "stop after this many seconds (default: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e7));
  record->callback([rf] { set_exit_code(run_record(*rf)); });
}

}  // namespace quiver::tools
