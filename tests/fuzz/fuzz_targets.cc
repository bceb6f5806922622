#include "fuzz_targets.h"

#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/grammar/retype.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/planner/planner.h"
#include "quiver/agents/rules/planner/plan_replay.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/replica/store/records.h"
#include "quiver/base/byte_codec.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"
#include "quiver/graph/state_parts.h"
#include "quiver/graph/world_file.h"
#include "quiver/agents/view/recording/history.h"
#include "quiver/agents/view/recording/record_file.h"
#include "quiver/interop/agm.h"
#include "quiver/interop/dsr.h"
#include "graph/interop/world_compare.h"
#include "quiver/base/rng.h"

namespace quiver::fuzz {
namespace {

using namespace graph;

void check(const Graph& g, const char* what) {
  auto v = g.check_invariants();
  if (!v.empty()) {
    std::fprintf(stderr, "%s: invariant violated: %s\n", what, v[0].c_str());
    std::abort();
  }
}

// A small populated replica, rebuilt for every input.
void populate(Graph& g) {
  auto tx = g.begin();
  auto w = *tx.create_node("world", "world");
  auto r = *tx.create_node("robot", "robot", {{Symbol("battery"), Value(0.5)}});
  auto p = *tx.create_node("person", "person");
  (void)tx.insert_edge(r, p, Symbol("is_with"));
  (void)tx.set_rt(w, r, Pose{}, 1);
  (void)tx.commit();
}

struct NullTransport : agents::Transport {
  void send(const agents::Sample&) override {}
};

}  // namespace

bool graph_delta(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  GraphDelta d;
  Status s = decode(bytes, d);
  // Joined in parts (as a replica joins a state), the same bytes are refused exactly when they
  // do not decode or are not a state, and a refusal joins nothing.
  Graph parts(ReplicaId{1, 1});
  populate(parts);
  const Digest128 before = parts.digest();
  GraphDelta scratch;
  Status ps = merge_state(parts, bytes, scratch, {}, {}, 3);
  if (ps.ok() != (s.ok() && d.kind == GraphDelta::Kind::kState) || (!ps.ok() && parts.digest() != before)) {
    std::fprintf(stderr, "a join in parts disagrees with decode(): %s\n", ps.ok() ? "joined" : ps.error().to_string().c_str());
    std::abort();
  }
  if (!s.ok()) {
    if (s.error().message.empty()) std::abort();  // every error must say what was wrong
    return false;
  }
  Graph g(ReplicaId{1, 1});
  populate(g);
  g.merge(d);
  check(g, "graph_delta");
  if (ps.ok() && parts.digest() != g.digest()) {
    std::fprintf(stderr, "a state joined in parts differs from the state joined whole\n");
    std::abort();
  }
  // Whatever was accepted must survive a round trip through the encoder.
  auto again = decode(encode(d));
  if (!again.ok()) {
    std::fprintf(stderr, "re-encoded delta does not decode: %s\n", again.error().to_string().c_str());
    std::abort();
  }
  // And the replica's state, encoded in parts, must decode and rebuild it.
  std::vector<std::uint8_t> state;
  encode_state(g, {}, state, 2);
  Graph rebuilt(ReplicaId{2, 1});
  auto st = decode(state);
  if (!st.ok() || (rebuilt.merge(*st), rebuilt.digest() != g.digest())) {
    std::fprintf(stderr, "a state encoded in parts does not rebuild its replica: %s\n",
                 st.ok() ? "different digest" : st.error().to_string().c_str());
    std::abort();
  }
  return true;
}

bool replication_samples(const std::uint8_t* data, std::size_t size) {
  Graph g(ReplicaId{1, 1});
  populate(g);
  NullTransport t;
  agents::Replicator rep(g, t);
  rep.start(0);
  std::int64_t now = 1000;
  bool framed = true;
  std::size_t at = 0;
  while (at < size) {
    if (size - at < 3 || data[at] >= agents::kDdsTopicCount) {
      framed = false;
      break;
    }
    const auto topic = static_cast<agents::DdsTopic>(data[at]);
    const std::size_t len = data[at + 1] | (std::size_t{data[at + 2]} << 8);
    at += 3;
    if (len > size - at) {
      framed = false;
      break;
    }
    agents::deliver_cdr_sample(rep, topic, std::span<const std::uint8_t>(data + at, len), now);
    at += len;
    now += 30'000'000;
    rep.tick(now);
  }
  rep.tick(now + 2'000'000'000);
  check(g, "replication_samples");
  return framed && rep.stats().rejected == 0;
}

bool dds_sample(int topic, const std::uint8_t* data, std::size_t size) {
  auto e = agents::decode_cdr_sample(static_cast<agents::DdsTopic>(topic), std::span<const std::uint8_t>(data, size));
  if (!e.ok()) {
    if (e.error().message.empty()) std::abort();
    return false;
  }
  Graph g(ReplicaId{1, 1});
  populate(g);
  NullTransport t;
  agents::Replicator rep(g, t);
  rep.start(0);
  rep.on_sample(*e, 1000);
  rep.tick(2'000'000'000);
  check(g, "dds_sample");
  return rep.stats().rejected == 0;
}

bool grammar_file(const std::uint8_t* data, std::size_t size) {
  auto parsed = agents::parse_grammar(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.aggl");
  if (!parsed.ok()) {
    if (parsed.error().message.find("fuzz.aggl:") != 0) {
      std::fprintf(stderr, "a grammar error without a location: %s\n", parsed.error().message.c_str());
      std::abort();
    }
    return false;
  }
  agents::GrammarChecker checker(std::move(*parsed));
  Graph g(ReplicaId{1, 1});
  populate(g);
  auto tx = g.begin();
  (void)tx.delete_edge(*g.find_node("robot"), *g.find_node("person"), Symbol("is_with"));
  (void)tx.insert_edge(*g.find_node("person"), *g.find_node("robot"), Symbol("is_with"));
  (void)checker.check(g, tx.ops());
  auto retype = g.begin();  // a retype: the person replaced by a patient of the same name
  (void)agents::replace_node_type(retype, *g.find_node("person"), "patient");
  (void)checker.check(g, retype.ops());
  (void)checker.all_violations(g);
  return true;
}

bool schema_file(const std::uint8_t* data, std::size_t size) {
  namespace sc = agents::schema;
  auto parsed = sc::Schema::parse(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.schema.json");
  if (!parsed.ok()) {
    if (parsed.error().message.find("fuzz.schema.json: ") != 0) {
      std::fprintf(stderr, "a schema error without the file's name: %s\n", parsed.error().message.c_str());
      std::abort();
    }
    return false;
  }
  // What it writes, it reads back as the same schema.
  const std::string text = parsed->to_json();
  auto again = sc::Schema::parse(text, "again");
  if (!again.ok() || again->to_json() != text) {
    std::fprintf(stderr, "a schema that does not read back: %s\n", again.ok() ? again->to_json().c_str() : again.error().message.c_str());
    std::abort();
  }
  auto schema = std::make_shared<const sc::Schema>(std::move(*parsed));
  for (const auto& [a, bases] : schema->node_types())
    for (const auto& [b, more] : schema->node_types()) (void)schema->is_a(a, b);  // inheritance ends
  // A replica under it commits what a churn draws, and merges a delta made without it.
  Graph g(ReplicaId{7, 1});
  populate(g);
  sc::SchemaAdmission adm(schema, nullptr);
  g.set_permission_check(adm.commit_check(g.replica().agent));
  g.set_type_change_check(adm.type_change_check());
  Graph free(ReplicaId{8, 1});
  populate(free);
  std::vector<GraphDelta> made;
  free.set_delta_sink([&](const GraphDelta& d) { made.push_back(d); });
  Rng rng(size);
  const char* kTypes[] = {"robot", "mug", "room", "ghost"};
  for (int i = 0; i < 8; ++i) {
    const auto before = g.digest();
    auto tx = g.begin();
    const auto nodes = g.nodes();
    if (!nodes.empty()) {
      const NodeId n = nodes[rng.below(nodes.size())];
      (void)tx.set(n, "label", Value(std::string("x")));
      (void)tx.set(n, "battery", Value(rng.uniform()));
      (void)tx.create_node(i % 2 ? "robot" : "mug", "fz" + std::to_string(i));
      (void)tx.insert_edge(n, nodes[rng.below(nodes.size())], "in");
    }
    if (!tx.commit().ok() && g.digest() != before) {
      std::fprintf(stderr, "a commit the schema refused changed the replica\n");
      std::abort();
    }
    // The same kinds of change by a replica without the schema (a rogue): merged under it below.
    auto ftx = free.begin();
    auto made_node = ftx.create_node(kTypes[rng.below(4)], "fr" + std::to_string(i));
    if (made_node.ok()) {
      if (rng.chance(0.5)) (void)ftx.set(*made_node, "battery", Value(rng.uniform() * 3 - 1));
      else (void)ftx.set(*made_node, "label", Value::int32(static_cast<std::int32_t>(i)));
      const auto fnodes = free.nodes();
      if (!fnodes.empty()) (void)ftx.insert_edge(*made_node, fnodes[rng.below(fnodes.size())], rng.chance(0.5) ? "in" : "near");
    }
    (void)ftx.commit();
  }
  for (const GraphDelta& d : made) {
    std::vector<std::uint8_t> bytes;
    encode(d, bytes, 1, 1);
    if (adm.admit_delta(d, bytes, {}, {}).ok()) g.merge(d);
  }
  check(g, "schema_file");
  return true;
}

bool mission_file(const std::uint8_t* data, std::size_t size) {
  auto parsed = agents::parse_mission(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.aggt");
  if (!parsed.ok()) {
    if (parsed.error().message.find("fuzz.aggt:") != 0) {
      std::fprintf(stderr, "a mission error without a location: %s\n", parsed.error().message.c_str());
      std::abort();
    }
    return false;
  }
  // A small domain over populate()'s world: the robot and the person swap who is with whom.
  static const char* kDomain = R"(name=fuzz
===
types
{
	(world) (robot) (person)
}
===
turn : active(1)
{
	{ r:robot(0,0) p:person(1,1) r->p(is_with) } => { r:robot(0,0) p:person(1,1) p->r(is_with) }
}
back : active(2)
{
	{ r:robot(0,0) p:person(1,1) p->r(is_with) } => { r:robot(0,0) p:person(1,1) r->p(is_with) r->r(busy) }
}
)";
  auto domain = agents::parse_grammar(kDomain, "fuzz_domain.aggl");
  if (!domain.ok()) std::abort();
  Graph g(ReplicaId{1, 1});
  populate(g);
  agents::MissionReport report = agents::check_mission(*parsed, g, domain->types, 10'000);
  if (!report.holds && report.missing.empty()) {
    std::fprintf(stderr, "a mission that does not hold with nothing missing\n");
    std::abort();
  }
  agents::symbolic::World world = agents::symbolic::read_world(g, domain->types);
  agents::planner::Domain d(*domain, world.vocabulary);
  auto compiled = agents::compile_mission(*parsed, world);
  if (!compiled.ok()) return true;
  agents::planner::PlannerOptions o;
  o.max_expansions = 200;
  o.max_world_increment = 2;
  auto plan = agents::planner::plan(d, world.state, *compiled, o);
  if (plan.found()) {
    agents::GrammarChecker checker(*domain);
    Status s = agents::planner::verify_plan(g, checker, world, plan, *parsed);
    if (!s.ok()) {
      std::fprintf(stderr, "a plan the guard refuses: %s\n", s.error().message.c_str());
      std::abort();
    }
  }
  return true;
}

bool recording_file(const std::uint8_t* data, std::size_t size) {
  auto rec = agents::recording::parse_recording(std::span<const std::uint8_t>(data, size), "fuzz.qrec");
  if (!rec.ok()) {
    if (rec.error().message.find("fuzz.qrec") == std::string::npos) std::abort();  // errors name the file
    return false;
  }
  agents::recording::History h;
  Graph g(agents::recording::replay_replica_id());
  for (auto& f : rec->changes) {
    g.merge(f.delta);
    h.add(std::move(f));
  }
  check(g, "recording_file");
  if (!h.empty() && !(h.state_after(h.end() - 1).value()->digest() == g.digest())) {
    std::fprintf(stderr, "recording_file: the history does not rebuild the replayed state\n");
    std::abort();
  }
  return true;
}

bool world_file(const std::uint8_t* data, std::size_t size) {
  Graph g(ReplicaId{1, 1});
  populate(g);
  Digest128 before = g.digest();
  auto r = load_world(g, std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
  if (!r.ok() && !(g.digest() == before)) {
    std::fprintf(stderr, "a rejected world file changed the graph: %s\n", r.error().to_string().c_str());
    std::abort();
  }
  check(g, "world_file");
  return r.ok();
}

namespace {

template <class Import, class Export>
bool foreign_world(const std::uint8_t* data, std::size_t size, const char* what, Import import, Export export_) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Graph g(ReplicaId{1, 1});
  populate(g);
  const Digest128 before = g.digest();
  auto r = import(g, text);
  if (!r.ok() && !(g.digest() == before)) {
    std::fprintf(stderr, "%s: a refused file changed the graph: %s\n", what, r.error().to_string().c_str());
    std::abort();
  }
  check(g, what);
  // The file's world alone (a populated graph refuses the names it already has), exported and
  // imported again: the same world, and no warning.
  Graph first(ReplicaId{2, 1});
  auto a = import(first, text);
  if (!a.ok()) {
    if (r.ok()) {
      std::fprintf(stderr, "%s: imported into a populated graph, refused into an empty one: %s\n", what,
                   a.error().to_string().c_str());
      std::abort();
    }
    return false;
  }
  check(first, what);
  const std::string out = export_(first).text;
  Graph second(ReplicaId{3, 1});
  interop::ImportOptions strict;
  strict.strict = true;
  auto b = import(second, out, strict);
  if (!b.ok()) {
    std::fprintf(stderr, "%s: an exported world does not import: %s\n%s\n", what, b.error().to_string().c_str(),
                 out.c_str());
    std::abort();
  }
  auto diff = interop::testing::world_differences(first, second, 1e-12);
  if (!diff.empty()) {
    std::fprintf(stderr, "%s: the world changed through export and import: %s\n", what, diff[0].c_str());
    std::abort();
  }
  return true;
}

}  // namespace

bool dsr_file(const std::uint8_t* data, std::size_t size) {
  return foreign_world(
      data, size, "dsr_file",
      [](Graph& g, std::string_view t, interop::ImportOptions o = {}) { return interop::import_dsr(g, t, "fuzz.json", o); },
      [](const Graph& g) { return interop::export_dsr(g); });
}

bool agm_file(const std::uint8_t* data, std::size_t size) {
  return foreign_world(
      data, size, "agm_file",
      [](Graph& g, std::string_view t, interop::ImportOptions o = {}) { return interop::import_agm(g, t, "fuzz.xml", o); },
      [](const Graph& g) { return interop::export_agm(g); });
}

// A store's log records and snapshots as read from disk: the input as it is (almost always a
// checksum mismatch), and sealed with a valid checksum so that the parser behind it is reached.
// Whatever decodes re-encodes to the same bytes, and a delta's payload goes through the codec as
// a reload would.
bool store_record(const std::uint8_t* data, std::size_t size) {
  using namespace agents::store;
  const std::span<const std::uint8_t> raw(data, size);
  std::vector<std::uint8_t> sealed(data, data + size);
  {
    const std::uint64_t c = record_checksum(raw);
    bytes::Writer(sealed).fixed64(c);
  }
  bool any = false;
  for (std::span<const std::uint8_t> in : {raw, std::span<const std::uint8_t>(sealed)}) {
    if (auto r = decode_record(in, "fuzz record"); r.ok()) {
      any = true;
      std::vector<std::uint8_t> again;
      switch (r->kind) {
        case RecordKind::kDelta: again = encode_delta_record(r->origin, r->lo, r->hi, r->payload); break;
        case RecordKind::kState: again = encode_state_record(r->applied, r->payload); break;
        case RecordKind::kSkipped: again = encode_skipped_record(r->origin, r->lo, r->hi); break;
      }
      if (r->kind != RecordKind::kSkipped) {
        GraphDelta d;
        if (decode(r->payload, d).ok()) {
          Graph g(ReplicaId{1, 1});
          g.merge(d);
        }
      }
      // Varints may be written longer than needed in the input: compare by decoding again.
      auto r2 = decode_record(again, "fuzz record again");
      if (!r2.ok() || r2->kind != r->kind || !(r2->origin == r->origin) || r2->lo != r->lo || r2->hi != r->hi ||
          !std::equal(r2->payload.begin(), r2->payload.end(), r->payload.begin(), r->payload.end())) {
        std::fprintf(stderr, "store_record: a decoded record does not re-encode to itself\n");
        std::abort();
      }
    }
    if (auto s = decode_snapshot(in, "fuzz snapshot"); s.ok()) {
      any = true;
      // The decoded snapshot's state is a view into the bytes: keep them alive.
      const std::vector<std::uint8_t> bytes = encode_snapshot(s->upto, s->applied, s->state);
      auto again = decode_snapshot(bytes, "again");
      if (!again.ok() || again->upto != s->upto ||
          !std::equal(again->state.begin(), again->state.end(), s->state.begin(), s->state.end())) {
        std::fprintf(stderr, "store_record: a decoded snapshot does not re-encode to itself\n");
        std::abort();
      }
    }
  }
  return any;
}

}  // namespace quiver::fuzz
