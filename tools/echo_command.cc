// quiver echo: the graph's changes on a live DDS domain, as they arrive (who, what, when), until
// interrupted; what `ros2 topic echo` is for a topic.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "commands.h"
#include "dds_options.h"
#include "observer.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/world_file.h"

namespace quiver::tools {
namespace {

using nlohmann::json;

struct EchoFlags {
  DdsFlags dds;
  std::vector<std::string> types;  ///< node or edge types to show (none: all)
  std::vector<std::string> nodes;  ///< node names to show, with their edges (none: all)
  std::vector<std::string> attrs;  ///< attribute names to show (none: all)
  bool json = false;
  int count = 0;          ///< stop after this many changes (0: never)
  double timeout_s = 0;   ///< stop after this many seconds (0: never)
  double wait_s = 2;      ///< how long to wait for the domain's graph before following it
};

// A value as the world file writes it (numbers and strings as JSON's, typed ones tagged).
json value_json(const graph::Value& v) { return json::parse(graph::value_to_json_text(v)); }

// One change per line: what it is, and the values it names as the graph holds them now (a
// deleted node or edge: the values it had).
class Printer {
 public:
  Printer(const EchoFlags& f, const graph::Graph& g, std::int64_t t0)
      : f_(f), g_(g), t0_(t0), nodes_(f.nodes.begin(), f.nodes.end()) {}

  int printed() const { return printed_; }

  void batch(const graph::ChangeBatch& b) {
    const double t = static_cast<double>(agents::monotonic_ns() - t0_) / 1e9;
    for (const graph::NodeChange& c : b.nodes) {
      const std::string name = c.kind == graph::ChangeKind::kDeleted ? c.name : g_.name_of(c.id);
      if (!nodes_.empty() && !nodes_.count(name)) continue;
      json values = json::object();
      if (c.kind == graph::ChangeKind::kDeleted) {
        for (const auto& [k, v] : c.values) values[k.str()] = value_json(v);
      } else {
        for (graph::Symbol a : c.attrs)
          if (const graph::Value* v = g_.attr(c.id, a)) values[a.str()] = value_json(*v);
          else values[a.str()] = nullptr;  // removed
      }
      emit(t, b, graph::to_string(c.kind), json{{"node", name}, {"type", c.type.str()}}, values, c.renamed);
    }
    // An edge's end by name, also when the node went in the same batch (its last name).
    auto end_name = [&](const graph::NodeId& id) {
      std::string n = g_.name_of(id);
      for (const graph::NodeChange& c : b.nodes)
        if (n.empty() && c.id == id && c.kind == graph::ChangeKind::kDeleted) n = c.name;
      return n;
    };
    for (const graph::EdgeChange& c : b.edges) {
      const std::string from = end_name(c.key.from), to = end_name(c.key.to);
      if (!nodes_.empty() && !nodes_.count(from) && !nodes_.count(to)) continue;
      json values = json::object();
      if (c.kind == graph::ChangeKind::kDeleted) {
        for (const auto& [k, v] : c.values) values[k.str()] = value_json(v);
      } else if (c.key.type == graph::symbols::rt()) {
        if (auto e = g_.rt_edge(c.key.to)) {
          const auto& p = e->pose;
          values["translation"] = json::array({p.translation[0], p.translation[1], p.translation[2]});
          values["stamp"] = e->stamp;
        }
      } else {
        for (graph::Symbol a : c.attrs)
          if (const graph::Value* v = g_.edge_attr(c.key, a)) values[a.str()] = value_json(*v);
          else values[a.str()] = nullptr;
      }
      json what{{"edge", {{"from", from.empty() ? c.key.from.to_string() : from}, {"to", to.empty() ? c.key.to.to_string() : to},
                          {"type", c.key.type.str()}}}};
      emit(t, b, graph::to_string(c.kind), what, values, false);
    }
  }

 private:
  void emit(double t, const graph::ChangeBatch& b, const char* kind, const json& what, const json& values,
            bool renamed) {
    if (f_.count > 0 && printed_ >= f_.count) return;
    ++printed_;
    if (f_.json) {
      json j = what;
      j["t_s"] = std::round(t * 1e3) / 1e3;
      j["origin"] = b.origin_name;
      j["local"] = b.local;
      j["kind"] = kind;
      j["values"] = values;
      if (renamed) j["renamed"] = true;
      std::cout << j.dump() << std::endl;
      return;
    }
    char when[32];
    std::snprintf(when, sizeof when, "%9.3f s", t);
    std::cout << when << "  " << b.origin_name << "  " << kind << " ";
    if (what.contains("node")) {
      std::cout << "node '" << what["node"].get<std::string>() << "' (" << what["type"].get<std::string>() << ")";
    } else {
      const json& e = what["edge"];
      std::cout << "edge '" << e["from"].get<std::string>() << "' -[" << e["type"].get<std::string>() << "]-> '"
                << e["to"].get<std::string>() << "'";
    }
    if (renamed) std::cout << " renamed";
    for (const auto& [k, v] : values.items()) std::cout << "  " << k << "=" << (v.is_null() ? "(removed)" : v.dump());
    std::cout << std::endl;
  }

  const EchoFlags& f_;
  const graph::Graph& g_;
  std::int64_t t0_;
  std::set<std::string> nodes_;
  int printed_ = 0;
};

int run_echo(const EchoFlags& f) {
  auto log = agents::named_logger("quiver echo");
  // A name of its own: an agent's id is its name's hash, and a second echo (or a restart) under
  // one name would retire the first as an older incarnation of the same agent.
  auto opened = open_observer(f.dds, "quiver-echo-" + std::to_string(::getpid()));
  if (!opened.ok()) {
    log->error("{}", opened.error().to_string());
    return 2;
  }
  agents::DdsReplica& r = **opened;
  // What the domain holds already is not news: follow from once this replica holds it (or from
  // --wait-s on, when nobody answers: then every change is news).
  if (Status s = wait_for_graph(r, f.dds, f.wait_s); !s.ok()) log->info("{}: following anyway", s.error().message);
  log->info("following DDS domain {}: {} nodes, {} live agents (Ctrl-C stops)", f.dds.domain, r.graph().node_count(),
            r.replicator().live_peer_count());
  const std::int64_t t0 = agents::monotonic_ns();
  Printer printer(f, r.graph(), t0);
  // A filter's lists are alternatives; --type and --attr must both hold: one filter after the other.
  graph::ChangeFilter by_type, by_attr;
  by_type.node_types = by_type.edge_types = f.types;
  by_attr.attributes = f.attrs;
  r.graph().subscribe(by_type, [&](const graph::ChangeBatch& b) { printer.batch(by_attr.select(b)); });
  agents::stop_on_signals();
  const std::int64_t deadline = f.timeout_s > 0 ? t0 + static_cast<std::int64_t>(f.timeout_s * 1e9) : 0;
  while (!agents::stop_requested() && (f.count == 0 || printer.printed() < f.count) &&
         (deadline == 0 || agents::monotonic_ns() < deadline))
    r.spin_once(50'000'000);
  return 0;
}

}  // namespace

void add_echo_command(CLI::App& app) {
  auto f = std::make_shared<EchoFlags>();
  auto* echo = app.add_subcommand(
      "echo",
      "Join a live DDS domain as an observer and print the graph's changes as they arrive: when, which agent, what "
      "(node or edge, created, updated or deleted) and the values it names, until Ctrl-C");
  f->dds.add_to(echo);
  echo->add_option("--type", f->types, "only nodes and edges of these types (repeat or comma-separate)")
      ->delimiter(',');
  echo->add_option("--node", f->nodes, "only these nodes (by name) and the edges that touch them")->delimiter(',');
  echo->add_option("--attr", f->attrs, "only changes that name these attributes")->delimiter(',');
  echo->add_flag("--json", f->json, "one JSON object per change");
  echo->add_option("--count", f->count, "stop after this many changes (0: never)")->check(CLI::NonNegativeNumber);
  echo->add_option("--timeout", f->timeout_s, "stop after this many seconds (0: never)")->check(CLI::Range(0.0, 1e7));
  echo->add_option("--wait", f->wait_s, "how long to wait for the domain's graph before following it")
      ->check(CLI::Range(0.0, 600.0))
      ->capture_default_str();
  echo->callback([f] { set_exit_code(run_echo(*f)); });
}

}  // namespace quiver::tools
