// The roles of the DDS benchmarks, one process each: writer, reader and joiner (`bench dds`),
// tracker and listener (`bench dds-tracking`).
#include "quiver/tools/bench/dds_roles.h"

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/base/rng.h"
#include "quiver/base/stage_marks.h"
#include "quiver/graph/graph.h"

namespace quiver::tools::bench {
namespace {

using agents::DdsReplica;
using agents::monotonic_ns;
using graph::NodeId;
using graph::Symbol;
using graph::Value;
using json = nlohmann::json;

constexpr std::int64_t kSec = 1'000'000'000;

// The role's replica, or null (logged) when it cannot be opened.
std::unique_ptr<DdsReplica> make_agent(const std::string& name, const ReplicaFactory& open) {
  agents::DdsReplicaOptions o;
  o.name = name;
  o.dds.max_blocking_ns = 2 * kSec;  // a benchmark wants back-pressure, not drops
  auto a = open(o);
  if (!a.ok()) {
    agents::named_logger(name)->error("{}", a.error().to_string());
    return nullptr;
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

// ------------------------------------------------------------------ throughput / latency / join

int writer_role(const DdsRole& f) {
  if (f.stages) stage_marks::enable();
  auto agent = make_agent("bench-writer", f.open);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  if (!a.spin_until(
          [&] { return a.replicator().live_peer_count() >= static_cast<std::size_t>(f.readers); },
          30 * kSec)) {
    agents::named_logger("bench writer")
        ->error("only {} of {} readers appeared", a.replicator().live_peer_count(), f.readers);
    return 1;
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
    for (long i = 0; i < n; ++i)
      (void)tx.set(ids[rng.below(1000)], attrs[rng.below(10)], Value(rng.uniform()));
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
  json stages = json::array();
  for (int i = 0; i < f.latency_samples; ++i) {
    auto tx = g.begin();
    const std::int64_t t0 = monotonic_ns();
    (void)tx.set(probe, Symbol("t"), Value(t0));
    (void)tx.commit();
    a.spin_for(1'000'000);
    // After the spin: a replica that coalesces its deltas (signed ones) publishes at its next tick.
    if (f.stages) {
      using stage_marks::at, stage_marks::Stage;
      stages.push_back({t0, at(Stage::kEncoded), at(Stage::kSigned), at(Stage::kWritten)});
    }
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
  if (f.stages) ready["stages"] = std::move(stages);
  std::cout << ready.dump() << std::endl;
  // Wait for the joiner (one more peer) to hold everything, then end the run.
  a.spin_until(
      [&] { return a.replicator().live_peer_count() > static_cast<std::size_t>(f.readers); },
      60 * kSec);
  wait_all_hold(a, 60 * kSec);
  set_phase(g, control, "done");
  a.spin_for(300'000'000);
  return 0;
}

int reader_role(const DdsRole& f) {
  if (f.stages) stage_marks::enable();
  auto agent = make_agent("bench-reader-" + std::to_string(f.id), f.open);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  std::vector<double> latencies_us;
  json stages = json::array();
  std::string phase;
  std::int64_t t_throughput_done = 0;
  const Symbol kPhase("phase"), kT("t");
  g.subscribe([&](const graph::ChangeBatch& b) {
    const std::int64_t now = monotonic_ns();
    for (const auto& n : b.nodes) {
      if (n.kind != graph::ChangeKind::kUpdated) continue;
      for (Symbol s : n.attrs) {
        if (s == kT && phase == "latency") {
          if (const auto* v = g.attr(n.id, kT)->get_if<std::int64_t>()) {
            latencies_us.push_back((now - *v) / 1000.0);
            if (f.stages) {
              using stage_marks::at, stage_marks::Stage;
              stages.push_back({*v, at(Stage::kWoken), at(Stage::kTaken), at(Stage::kDecoded), at(Stage::kAdmitted),
                                at(Stage::kMerging), now});
            }
          }
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
  if (f.stages) out["stages"] = std::move(stages);
  out["deltas_applied"] = a.replicator().stats().deltas_applied;
  out["states_applied"] = a.replicator().stats().states_applied;
  std::cout << out.dump() << std::endl;
  return 0;
}

int joiner_role(const DdsRole& f) {
  const std::int64_t t_start = monotonic_ns();
  auto agent = make_agent("bench-joiner", f.open);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  const std::int64_t t_created = monotonic_ns();
  const std::size_t want = static_cast<std::size_t>(f.join_nodes) + 2;
  bool ok = a.spin_until([&] { return a.graph().node_count() >= want && a.replicator().synced(); },
                         60 * kSec);
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
  return 0;
}

// The human tracking load of the AGM paper.
constexpr int kPeople = 2, kJoints = 15, kHz = 30;

int tracker_role(const DdsRole& f) {
  auto agent = make_agent("tracker", f.open);
  if (!agent) return 2;
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
        joints[p].push_back(
            *tx.create_node("joint", "person" + std::to_string(p) + "_joint" + std::to_string(j)));
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
  return 0;
}

int listener_role(const DdsRole& f) {
  auto agent = make_agent("listener-" + std::to_string(f.id), f.open);
  if (!agent) return 2;
  DdsReplica& a = *agent;
  graph::Graph& g = a.graph();
  std::vector<double> latencies_us;
  bool done = false;
  g.subscribe([&](const graph::ChangeBatch& b) {
    const std::int64_t now = monotonic_ns();
    for (const auto& e : b.edges) {
      if (e.kind != graph::ChangeKind::kUpdated || !(e.key.type == graph::symbols::rt())) continue;
      if (auto rt = g.rt_edge(e.key.to); rt && rt->stamp > 0)
        latencies_us.push_back((now - rt->stamp) / 1000.0);
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
  return 0;
}

}  // namespace

int run_dds_role(const DdsRole& r) {
  if (r.role == "writer") return writer_role(r);
  if (r.role == "reader") return reader_role(r);
  if (r.role == "joiner") return joiner_role(r);
  if (r.role == "tracker") return tracker_role(r);
  if (r.role == "listener") return listener_role(r);
  return 2;
}

}  // namespace quiver::tools::bench
