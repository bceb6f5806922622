// The roles of `quiver bench dds-scale`, one process each: the writer (a change every 1/rate s,
// stamped with the monotonic clock every process on the host shares), the members (what each
// change cost them to receive: latency; what they spend: CPU while changes flow and while idle)
// and the joiner (one more agent: how long until it holds everything).
#include "quiver/tools/bench/scale_roles.h"

#include <sys/resource.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/agents/runtime/process/subprocess.h"
#include "quiver/graph/graph.h"

namespace quiver::tools::bench {
namespace {

using agents::DdsReplica;
using agents::monotonic_ns;
using graph::Symbol;
using graph::Value;
using json = nlohmann::json;

constexpr std::int64_t kSec = 1'000'000'000;

// CPU time (user + system, all threads) this process has used.
std::int64_t cpu_ns() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * kSec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1000L;
}

std::unique_ptr<DdsReplica> open_replica(const std::string& name, const ScaleRole& f) {
  agents::DdsReplicaOptions o;
  o.name = name;
  auto a = f.open(o);
  if (!a.ok()) {
    agents::named_logger(name)->error("{}", a.error().to_string());
    return nullptr;
  }
  return std::move(*a);
}

std::string phase(const graph::Graph& g) {
  auto n = g.find_node("scale");
  const Value* v = n ? g.attr(*n, "phase") : nullptr;
  auto s = v ? v->as<std::string>() : Result<std::string>(make_error(ErrorCode::kNotFound, ""));
  return s.ok() ? *s : "";
}

void set_phase(graph::Graph& g, const char* p) {
  auto n = g.find_node("scale");
  if (!n) return;
  auto tx = g.begin();
  (void)tx.set(*n, Symbol("phase"), Value(p));
  (void)tx.commit();
}

// CPU used over `seconds` of idle time (nothing written), as a share of one core.
double idle_cpu_pct(DdsReplica& a, double seconds) {
  const std::int64_t c0 = cpu_ns(), t0 = monotonic_ns();
  a.spin_for(static_cast<std::int64_t>(seconds * kSec));
  return 100.0 * static_cast<double>(cpu_ns() - c0) / static_cast<double>(monotonic_ns() - t0);
}

int writer(const ScaleRole& f) {
  auto agent = open_replica("scale-writer", f);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  const std::int64_t t_open = monotonic_ns();
  graph::NodeId node;
  {
    auto tx = g.begin();
    node = *tx.create_node("bench", "scale");
    (void)tx.set(node, Symbol("phase"), Value("joining"));
    (void)tx.commit();
  }
  const auto others = static_cast<std::size_t>(f.agents - 1);
  // Progress every 10 s while peers are missing: a run that does not start says why.
  std::int64_t next_word = t_open + 10 * kSec;
  const bool all = a.spin_until(
      [&] {
        const std::size_t live = a.replicator().live_peer_count();
        if (live < others && monotonic_ns() >= next_word) {
          next_word += 10 * kSec;
          agents::named_logger("scale-writer")
              ->info("{} of {} peers live, {} lost", live, others, a.transport().stats().peers_lost);
        }
        return live >= others;
      },
      300 * kSec);
  const double ready_ms = static_cast<double>(monotonic_ns() - t_open) / 1e6;
  // The members' first pulls (the node) settle, and so does the start of many processes.
  a.spin_for(static_cast<std::int64_t>(f.settle_s * 1e9));
  const std::int64_t period = static_cast<std::int64_t>(kSec / f.rate);
  const std::int64_t c0 = cpu_ns(), t0 = monotonic_ns();
  std::int64_t next = t0;
  for (long i = 0; i < f.changes; ++i) {
    while (monotonic_ns() < next) a.spin_once(next - monotonic_ns());
    auto tx = g.begin();
    (void)tx.set(node, Symbol("seq"), Value(static_cast<std::int64_t>(i)));
    (void)tx.set(node, Symbol("t"), Value(monotonic_ns()));
    (void)tx.commit();
    // Each change its own delta: a writer behind its schedule (a stall) would otherwise send the
    // changes made before its next round as one, and the members would never see the ones between.
    a.replicator().flush();
    next += period;
  }
  const double run_s = static_cast<double>(monotonic_ns() - t0) / 1e9;
  const double run_cpu = 100.0 * static_cast<double>(cpu_ns() - c0) / (run_s * 1e9);
  a.spin_for(kSec);  // the last changes arrive everywhere
  set_phase(g, "idle");
  const double idle_cpu = idle_cpu_pct(a, f.idle_s);
  json out{{"role", "writer"},        {"all_joined", all},       {"ready_ms", ready_ms},
           {"peers", a.replicator().live_peer_count()}, {"peers_lost", a.transport().stats().peers_lost},
           {"run_s", run_s}, {"cpu_run_pct", run_cpu},
           {"cpu_idle_pct", idle_cpu}, {"rss_kb", agents::resident_kb()}};
  std::cout << out.dump() << std::endl;
  a.spin_until([&] { return phase(g) == "end"; }, 300 * kSec);
  a.spin_for(kSec / 2);
  return 0;
}

int member(const ScaleRole& f) {
  auto agent = open_replica("scale-member-" + std::to_string(f.id), f);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  std::vector<double> latency_us(static_cast<std::size_t>(f.changes), -1.0);
  std::int64_t c_first = -1, t_first = 0;
  g.subscribe([&](const graph::ChangeBatch& b) {
    const std::int64_t now = monotonic_ns();
    for (const auto& n : b.nodes) {
      const Value* seq = g.attr(n.id, "seq");
      const Value* t = g.attr(n.id, "t");
      if (!seq || !t) continue;
      auto s = seq->as<std::int64_t>();
      auto stamp = t->as<std::int64_t>();
      if (!s.ok() || !stamp.ok() || *s < 0 || *s >= f.changes) continue;
      if (c_first < 0) {
        c_first = cpu_ns();
        t_first = now;
      }
      double& slot = latency_us[static_cast<std::size_t>(*s)];
      if (slot < 0) slot = static_cast<double>(now - *stamp) / 1e3;
    }
  });
  const std::int64_t budget = static_cast<std::int64_t>((static_cast<double>(f.changes) / f.rate + 300) * kSec);
  a.spin_until([&] { return phase(g) == "idle"; }, budget);
  const double run_cpu =
      c_first < 0 ? 0 : 100.0 * static_cast<double>(cpu_ns() - c_first) / static_cast<double>(monotonic_ns() - t_first);
  const double idle_cpu = idle_cpu_pct(a, f.idle_s);
  json out{{"role", "member"},        {"id", f.id},           {"latencies_us", latency_us},
           {"cpu_run_pct", run_cpu},   {"cpu_idle_pct", idle_cpu},
           {"peers", a.replicator().live_peer_count()}, {"rss_kb", agents::resident_kb()},
           {"executable", std::filesystem::path(agents::self_executable()).filename().string()}};
  std::cout << out.dump() << std::endl;
  a.spin_until([&] { return phase(g) == "end"; }, 300 * kSec);
  a.spin_for(kSec / 2);
  return 0;
}

int joiner(const ScaleRole& f) {
  const std::int64_t t0 = monotonic_ns();
  auto agent = open_replica("scale-joiner", f);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  const std::int64_t t_open = monotonic_ns();
  const bool ok = a.spin_until(
      [&] {
        auto n = g.find_node("scale");
        const Value* seq = n ? g.attr(*n, "seq") : nullptr;
        auto s = seq ? seq->as<std::int64_t>() : Result<std::int64_t>(make_error(ErrorCode::kNotFound, ""));
        return s.ok() && *s == f.changes - 1;
      },
      120 * kSec);
  const std::int64_t t_synced = monotonic_ns();
  json out{{"role", "joiner"},
           {"synced", ok},
           {"join_ms", static_cast<double>(t_synced - t_open) / 1e6},
           {"join_ms_from_process_start", static_cast<double>(t_synced - t0) / 1e6},
           {"peers", a.replicator().live_peer_count()}};
  std::cout << out.dump() << std::endl;
  set_phase(g, "end");
  a.spin_for(2 * kSec);
  return 0;
}

}  // namespace

int run_scale_role(const ScaleRole& r) {
  if (r.role == "scale-writer") return writer(r);
  if (r.role == "scale-member") return member(r);
  if (r.role == "scale-joiner") return joiner(r);
  return 2;
}

}  // namespace quiver::tools::bench
