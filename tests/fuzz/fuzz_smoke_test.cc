// Seeded mutation fuzzing with any compiler: valid inputs (real deltas, CDR samples and world files)
// are mutated (bit flips, truncation, insertion, splicing of numbers) and fed to the same fuzz
// targets the libFuzzer binaries use. Deterministic per seed.

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_targets.h"
#include "quiver/agents/replica/store/records.h"
#include "quiver/agents/view/recording/record_file.h"
#include "quiver/graph/graph.h"
#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/graph/codec.h"
#include "quiver/base/rng.h"
#include "quiver/sim/workload.h"
#include "test_seed.h"

namespace quiver::fuzz {
namespace {

std::vector<std::uint8_t> mutate(const std::vector<std::uint8_t>& in, Rng& rng) {
  std::vector<std::uint8_t> out = in;
  int edits = 1 + static_cast<int>(rng.below(4));
  for (int e = 0; e < edits; ++e) {
    switch (rng.below(6)) {
      case 0:
        if (!out.empty()) out[rng.below(out.size())] ^= static_cast<std::uint8_t>(1u << rng.below(8));
        break;
      case 1:
        if (!out.empty()) out.resize(rng.below(out.size()));
        break;
      case 2:
        out.insert(out.begin() + static_cast<long>(rng.below(out.size() + 1)), static_cast<std::uint8_t>(rng.below(256)));
        break;
      case 3:
        if (!out.empty()) out[rng.below(out.size())] = 0xff;  // huge varints / lengths
        break;
      case 4:
        if (!out.empty()) out[rng.below(out.size())] = static_cast<std::uint8_t>(rng.below(4));
        break;
      default:
        if (out.size() > 2) out.erase(out.begin() + static_cast<long>(rng.below(out.size())));
    }
  }
  return out;
}

// QUIVER_FUZZ_CORPUS=<dir> writes the seed inputs there (for the libFuzzer binaries).
void maybe_save(const char* sub, const std::vector<std::vector<std::uint8_t>>& inputs) {
  const char* dir = std::getenv("QUIVER_FUZZ_CORPUS");
  if (!dir) return;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    std::string path = std::string(dir) + "/" + sub + "/seed" + std::to_string(i);
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
      std::fwrite(inputs[i].data(), 1, inputs[i].size(), f);
      std::fclose(f);
    }
  }
}

std::vector<std::vector<std::uint8_t>> delta_corpus(Rng& rng) {
  std::vector<std::vector<std::uint8_t>> corpus;
  graph::Graph g(graph::ReplicaId{7, 1});
  g.set_delta_sink([&](const graph::GraphDelta& d) { corpus.push_back(graph::encode(d)); });
  sim::Churn churn;
  for (int i = 0; i < 40; ++i) churn.step(g, rng, i);
  auto some = g.nodes();
  if (!some.empty()) {  // a delta carrying a rule claim
    (void)g.annotate_commit("someRule", {{"x", some.front()}, {"y", some.back()}});
    auto tx = g.begin();
    (void)tx.set(some.front(), "claimed", graph::Value(true));
    (void)tx.commit();
  }
  corpus.push_back(graph::encode(g.state()));
  return corpus;
}

// Inputs that once crashed a fuzzer or showed a defect, replayed forever. Every folder the test
// loops over must exist and hold something (a missing folder would make it pass on nothing).
std::vector<std::vector<std::uint8_t>> regressions(const char* target) {
  std::vector<std::vector<std::uint8_t>> out;
  std::filesystem::path dir = std::filesystem::path(QUIVER_FUZZ_REGRESSIONS) / target;
  EXPECT_TRUE(std::filesystem::is_directory(dir)) << dir << " is missing";
  if (!std::filesystem::is_directory(dir)) return out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::ifstream f(e.path(), std::ios::binary);
    out.emplace_back(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  EXPECT_FALSE(out.empty()) << dir << " holds no input";
  return out;
}

TEST(FuzzSmokeTest, Regressions) {
  // Each of them is bad input: it must be refused (and must not crash).
  struct Target {
    const char* folder;
    bool (*run)(const std::uint8_t*, std::size_t);
  };
  static bool (*const kDds[])(const std::uint8_t*, std::size_t) = {
      [](const std::uint8_t* d, std::size_t n) { return dds_sample(0, d, n); },
      [](const std::uint8_t* d, std::size_t n) { return dds_sample(1, d, n); },
      [](const std::uint8_t* d, std::size_t n) { return dds_sample(2, d, n); },
      [](const std::uint8_t* d, std::size_t n) { return dds_sample(3, d, n); },
      [](const std::uint8_t* d, std::size_t n) { return dds_sample(4, d, n); }};
  for (Target t : {Target{"graph_delta", graph_delta}, Target{"replication_samples", replication_samples},
                   Target{"world_file", world_file}, Target{"grammar_file", grammar_file},
                   Target{"recording_file", recording_file}, Target{"dsr_file", dsr_file},
                   Target{"agm_file", agm_file}, Target{"mission_file", mission_file},
                   Target{"schema_file", schema_file},
                   Target{"store_record", store_record},
                   Target{"dds_summary", kDds[0]}, Target{"dds_delta", kDds[1]}, Target{"dds_pull", kDds[2]},
                   Target{"dds_state", kDds[3]}, Target{"dds_bye", kDds[4]}}) {
    int n = 0;
    for (const auto& in : regressions(t.folder)) {
      EXPECT_FALSE(t.run(in.data(), in.size())) << t.folder << " input " << n << " was accepted";
      ++n;
    }
    std::printf("[fuzz] %s: %d regression inputs refused\n", t.folder, n);
  }
}

TEST(FuzzSmokeTest, GrammarFiles) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.GrammarFiles", 80);
  Rng rng(base);
  const std::string quiver_text = R"(grammar g
types { robot person room object mug : object }
allow attributes
rule meet : active {
  { r:robot p:person  !r->p(is_with) } => { r:robot p:person  r->p(is_with) }
  precondition { not exists o:object { r->o(carrying) } and r.battery > 0.2 or has p.name }
}
rule leave : passive {
  { r:robot p:person  r->p(is_with) } => { r:robot p:person }
  forall m:mug { { r->m(carrying) } => { } }
}
constraint alone { forbid { r:robot p:person q:person  r->p(is_with)  r->q(is_with) } repair by x: delete oldest }
)";
  // AGM's dialect (docs/grammar.md): header, types with inheritance, positions, '*' links, a
  // retype, precondition and effect, success, dormant, activates, hierarchical and combo rules.
  const std::string agm_text = R"(name=fuzz
fontName=Arial
vertexDiameter=40
===
types
{
	(world)
	(robot)
	(person)
	(patient : person)
	(object)
}
===
turn : active(2) success(0.9)
{
	{
		r:robot(0,0)
		p:person(100,0)
		r->p(is_with)
		p->r(is_with)*
	}
	=>
	{
		r:robot(0,0)
		p:person(100,0)
		p->r(is_with)
	}
	precondition
	{
		(and
			(not (exists o:object (carrying r o)))
			(or (= r r) (forall q:person (when (is_with r q) (= q p))))
		)
	}
	effect
	{
		(forall o:object (when (carrying r o) (and (not (near o r)) (near o p))))
	}
}

diagnose : passive(1)
{
	{
		p:person(0,0)
		r:robot(0,100)
		r->p(is_with)
	}
	=>
	{
		p:patient(0,0)
		r:robot(0,100)
		r->p(is_with)
	}
	effect
	{
		(and (create f object) (near f p) (retype r robot) (when (carrying r r) (delete f)))
	}
}

dormant back : active(1) activates(turn)
{
	{ r:robot(0,0) p:person(1,1) p->r(is_with) } => { r:robot(0,0) p:person(1,1) r->p(is_with) }
}

hierarchical swap : active(3)
{
	{ r:robot(0,0) p:person(1,1) r->p(is_with) } => { r:robot(0,0) p:person(1,1) r->r(busy) }
}

twice : active(4)
{
	turn as a
	back as b optional
	where:
	a.r = b.r
	a.p = b.p
}
)";
  std::vector<std::vector<std::uint8_t>> seeds;
  for (const std::string* text : {&quiver_text, &agm_text}) seeds.emplace_back(text->begin(), text->end());
  maybe_save("grammar", seeds);
  for (const auto& seed : seeds) {
    ASSERT_TRUE(grammar_file(seed.data(), seed.size()));
    int accepted = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      auto m = mutate(seed, rng);
      accepted += grammar_file(m.data(), m.size());
    }
    std::printf("[fuzz] %d of %d mutated grammar files parsed\n", accepted, n);
    EXPECT_GT(accepted, 0);
  }
}

TEST(FuzzSmokeTest, MissionFiles) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.MissionFiles", 81);
  Rng rng(base);
  const std::string holds = "{\n\trobot_c:robot(0,0)\n\tp:person(1,1)\n\trobot_c->p(is_with)\n}\nprecondition\n{\n}\n";
  const std::string plan = R"({
	r:robot(0,0)
	p:person(10,10)
	p->r(is_with)
	r->r(busy)*
	r->p(is_with)*
}
precondition
{
	(and (not (exists q:person (is_with r q))) (forall x:person (when (is_with x r) (= x p))))
}
)";
  std::vector<std::vector<std::uint8_t>> seeds;
  for (const std::string* text : {&holds, &plan}) seeds.emplace_back(text->begin(), text->end());
  maybe_save("mission", seeds);
  for (const auto& seed : seeds) {
    ASSERT_TRUE(mission_file(seed.data(), seed.size()));
    int accepted = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      auto m = mutate(seed, rng);
      accepted += mission_file(m.data(), m.size());
    }
    std::printf("[fuzz] %d of %d mutated missions parsed\n", accepted, n);
    EXPECT_GT(accepted, 0);
  }
}

TEST(FuzzSmokeTest, SchemaFiles) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.SchemaFiles", 83);
  Rng rng(base);
  const std::string full = R"({"quiver_schema": 1,
  "node_types": {"object": {}, "mug": {"is": "object"}, "cup": {"is": ["object", "mug"]}, "room": {}, "robot": {}},
  "edge_types": {"in": {"from": ["object", "robot"], "to": ["room"]}, "RT": {}},
  "attributes": {"battery": {"type": "double", "unit": "1", "min": 0, "max": 1, "on": ["robot"], "writers": ["panel"]},
                 "label": {"type": "string"}, "note": {"type": "any"}, "since": {"type": "int64", "on": ["in"]}}})";
  const std::string open = R"({"quiver_schema": 1, "open": true, "attributes": {"label": {"type": "int32", "max": 5}}})";
  std::vector<std::vector<std::uint8_t>> seeds;
  for (const std::string* text : {&full, &open}) seeds.emplace_back(text->begin(), text->end());
  maybe_save("schema", seeds);
  for (const auto& seed : seeds) {
    ASSERT_TRUE(schema_file(seed.data(), seed.size()));
    int accepted = 0;
    const int n = 5000;
    for (int i = 0; i < n; ++i) {
      auto m = mutate(seed, rng);
      accepted += schema_file(m.data(), m.size());
    }
    std::printf("[fuzz] %d of %d mutated schemas parsed\n", accepted, n);
    EXPECT_GT(accepted, 0);
  }
}

TEST(FuzzSmokeTest, GraphDeltaDecoder) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.GraphDeltaDecoder", 77);
  Rng rng(base);
  auto corpus = delta_corpus(rng);
  maybe_save("delta", corpus);
  for (const auto& c : corpus) ASSERT_TRUE(graph_delta(c.data(), c.size()));
  int accepted = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    auto m = mutate(rng.pick(corpus), rng);
    accepted += graph_delta(m.data(), m.size());
  }
  std::printf("[fuzz] %d of %d mutated deltas decoded and were merged\n", accepted, n);
  EXPECT_GT(accepted, n / 50) << "the mutations must reach the merge, not only the header checks";
  EXPECT_LT(accepted, n) << "some mutations must be rejected";
}

// A session as a replica receives it: the samples one replicator sends while its graph churns,
// framed as the replication_samples target reads them, mutated.
TEST(FuzzSmokeTest, ReplicationSamples) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.ReplicationSamples", 78);
  Rng rng(base);
  struct Capture : agents::Transport {
    std::vector<std::uint8_t> stream;
    void send(const agents::Sample& s) override {
      const agents::CdrSample c = agents::encode_cdr_sample(s);
      if (c.bytes.size() > 0xffff) return;  // a record holds up to 64 KiB
      stream.push_back(static_cast<std::uint8_t>(c.topic));
      stream.push_back(static_cast<std::uint8_t>(c.bytes.size() & 0xff));
      stream.push_back(static_cast<std::uint8_t>(c.bytes.size() >> 8));
      stream.insert(stream.end(), c.bytes.begin(), c.bytes.end());
    }
  } cap;
  graph::Graph g(graph::ReplicaId{9, 1});
  agents::Replicator rep(g, cap);
  rep.start(0);
  sim::Churn churn;
  std::vector<std::vector<std::uint8_t>> sessions;
  for (int i = 0; i < 30; ++i) {
    churn.step(g, rng, i);
    rep.tick(i * 100'000'000LL);
    if (i % 10 == 9) sessions.push_back(std::exchange(cap.stream, {}));
  }
  ASSERT_FALSE(sessions.front().empty());
  maybe_save("samples", sessions);
  for (const auto& s : sessions) ASSERT_TRUE(replication_samples(s.data(), s.size()));
  int accepted = 0;
  const int n = 3000;
  for (int i = 0; i < n; ++i) {
    auto m = mutate(rng.pick(sessions), rng);
    accepted += replication_samples(m.data(), m.size());
  }
  std::printf("[fuzz] %d of %d mutated sample streams accepted\n", accepted, n);
  EXPECT_GT(accepted, n / 50);
  EXPECT_LT(accepted, n) << "some mutations must be rejected";
}

// The CDR samples a rogue can publish on each DDS topic: real samples (from a churning
// replicator's messages, in every encoding Cyclone accepts) mutated.
TEST(FuzzSmokeTest, DdsSamples) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.DdsSamples", 81);
  Rng rng(base);
  struct Capture : agents::Transport {
    std::vector<agents::Sample> samples;
    void send(const agents::Sample& s) override { samples.push_back(s); }
  } cap;
  graph::Graph g(graph::ReplicaId{9, 1});
  agents::Replicator rep(g, cap);
  rep.start(0);
  sim::Churn churn;
  for (int i = 0; i < 30; ++i) {
    churn.step(g, rng, i);
    rep.tick(i * 100'000'000LL);
  }
  // Messages of every kind: pulls, state chunks and a goodbye too.
  const graph::ReplicaId to{3, 1};
  cap.samples.push_back(
      {g.replica(), to, agents::PullMsg{7, agents::to_ranges(rep.applied()), agents::to_ranges(g.context())}});
  cap.samples.push_back({g.replica(), to,
                         agents::StateMsg{7, 0, 1, agents::to_ranges(rep.applied()),
                                          std::make_shared<const std::vector<std::uint8_t>>(graph::encode(g.state()))}});
  cap.samples.push_back({g.replica(), to, agents::ByeMsg{}});
  std::vector<std::vector<std::vector<std::uint8_t>>> corpus(agents::kDdsTopicCount);
  for (const agents::Sample& one : cap.samples) {
    const auto t = static_cast<std::size_t>(agents::topic_of(one.message));
    for (int xcdr : {1, 2})
      for (bool le : {true, false}) corpus[t].push_back(agents::encode_cdr_sample(one, xcdr, le).bytes);
  }
  static constexpr const char* kDirs[] = {"dds_summary", "dds_delta", "dds_pull", "dds_state", "dds_bye"};
  for (std::size_t t = 0; t < corpus.size(); ++t) {
    ASSERT_FALSE(corpus[t].empty()) << kDirs[t];
    maybe_save(kDirs[t], corpus[t]);
    for (const auto& c : corpus[t]) ASSERT_TRUE(dds_sample(static_cast<int>(t), c.data(), c.size())) << kDirs[t];
    int accepted = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      auto m = mutate(rng.pick(corpus[t]), rng);
      accepted += dds_sample(static_cast<int>(t), m.data(), m.size());
    }
    std::printf("[fuzz] %s: %d of %d mutated samples accepted\n", kDirs[t], accepted, n);
    EXPECT_GT(accepted, 0) << kDirs[t];
    EXPECT_LT(accepted, n) << kDirs[t];
  }
}

TEST(FuzzSmokeTest, WorldFiles) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.WorldFiles", 79);
  Rng rng(base);
  const std::string doc = R"({"quiver_world": 1,
    "nodes": [{"name": "a", "type": "room", "attrs": {"x": 1.5, "n": {"int32": 3}, "v": {"vec3f": [1,2,3]}}},
              {"name": "b", "type": "robot", "attrs": {"m": {"mat4d": [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}}}],
    "edges": [{"from": "b", "to": "a", "type": "in"}],
    "rt": [{"parent": "a", "child": "b", "translation": [1,2,3], "rpy": [0,0,1.57]}]})";
  std::vector<std::uint8_t> seed(doc.begin(), doc.end());
  maybe_save("world", {seed});
  ASSERT_TRUE(world_file(seed.data(), seed.size()));
  int accepted = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    auto m = mutate(seed, rng);
    accepted += world_file(m.data(), m.size());
  }
  std::printf("[fuzz] %d of %d mutated world files loaded\n", accepted, n);
  EXPECT_GT(accepted, 0);
}

// CORTEX and AGM worlds: the interop fixtures (every layout, type code and construct), mutated.
TEST(FuzzSmokeTest, ForeignWorldFiles) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.ForeignWorldFiles", 89);
  Rng rng(base);
  struct Format {
    const char* dir;  // fixtures and libFuzzer corpus folder
    bool (*run)(const std::uint8_t*, std::size_t);
  };
  for (Format f : {Format{"dsr", dsr_file}, Format{"agm", agm_file}}) {
    std::vector<std::vector<std::uint8_t>> seeds;
    for (const auto& e : std::filesystem::directory_iterator(std::string(QUIVER_INTEROP_FIXTURES) + "/" + f.dir)) {
      std::ifstream in(e.path(), std::ios::binary);
      seeds.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ASSERT_GE(seeds.size(), 2u) << f.dir;
    maybe_save(f.dir, seeds);
    for (const auto& s : seeds) ASSERT_TRUE(f.run(s.data(), s.size())) << f.dir << ": a fixture is refused";
    int accepted = 0;
    const int n = 6000;
    for (int i = 0; i < n; ++i) {
      auto m = mutate(seeds[rng.below(seeds.size())], rng);
      accepted += f.run(m.data(), m.size());
    }
    std::printf("[fuzz] %s: %d of %d mutated worlds imported (and round-tripped)\n", f.dir, accepted, n);
    EXPECT_GT(accepted, 0) << f.dir;
    EXPECT_LT(accepted, n) << f.dir;
  }
}

TEST(FuzzSmokeTest, RecordingFiles) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.RecordingFiles", 83);
  Rng rng(base);
  // A real recording: a state change, then deltas of two writers (nodes, an edge, attributes, RT).
  graph::Graph a(graph::ReplicaId{11, 1}), b(graph::ReplicaId{12, 1});
  std::vector<std::uint8_t> seed;
  agents::recording::encode_header(0, seed);
  auto change = [&](std::int64_t t, const char* origin, const graph::GraphDelta& d) {
    agents::recording::encode_change({t, origin, d}, seed);
  };
  a.set_delta_sink([&](const graph::GraphDelta& d) { change(1, "a", d); });
  b.set_delta_sink([&](const graph::GraphDelta& d) { change(2, "b", d); });
  {
    auto tx = a.begin();
    auto w = *tx.create_node("world", "world");
    auto r = *tx.create_node("robot", "robot", {{graph::Symbol("battery"), graph::Value(0.5)}});
    (void)tx.set_rt(w, r, graph::Pose{}, 1);
    (void)tx.commit();
  }
  {
    auto tx = b.begin();
    auto k = *tx.create_node("room", "kitchen", {{graph::Symbol("area"), graph::Value(12.5)}});
    auto r = *tx.create_node("robot", "r2");
    (void)tx.insert_edge(r, k, graph::Symbol("in"));
    (void)tx.set_rt(k, r, graph::Pose{{1, 2, 3}, {1, 0, 0, 0}}, 5);
    (void)tx.commit();
  }
  maybe_save("recording", {seed});
  ASSERT_TRUE(recording_file(seed.data(), seed.size()));
  int accepted = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    auto m = mutate(seed, rng);
    accepted += recording_file(m.data(), m.size());
  }
  std::printf("[fuzz] %d of %d mutated recordings replayed\n", accepted, n);
  EXPECT_GT(accepted, 0);
}

}  // namespace
TEST(FuzzSmokeTest, StoreRecords) {
  const auto base = quiver::testing::base_seed("FuzzSmokeTest.StoreRecords", 84);
  Rng rng(base);
  // Real records of each kind and a snapshot, without their checksums: the target seals its
  // input, so mutations reach the record parser and the codec behind it.
  graph::Graph g(graph::ReplicaId{21, 1});
  std::vector<std::vector<std::uint8_t>> seeds;
  std::uint64_t seq = 0;
  g.set_delta_sink([&](const graph::GraphDelta& d) {
    std::vector<std::uint8_t> bytes;
    graph::encode(d, bytes, seq + 1, seq + 1);
    ++seq;
    seeds.push_back(agents::store::encode_delta_record(g.replica(), seq, seq, bytes));
  });
  {
    auto tx = g.begin();
    auto w = *tx.create_node("world", "world");
    auto r = *tx.create_node("robot", "robot", {{graph::Symbol("battery"), graph::Value(0.5)}});
    (void)tx.set_rt(w, r, graph::Pose{{1, 2, 3}, {1, 0, 0, 0}}, 1);
    (void)tx.insert_edge(r, r, graph::Symbol("moving"));
    (void)tx.commit();
  }
  const std::vector<std::uint8_t> state = graph::encode(g.state());
  seeds.push_back(agents::store::encode_state_record(g.context(), state));
  seeds.push_back(agents::store::encode_skipped_record(g.replica(), 3, 9));
  seeds.push_back(agents::store::encode_snapshot(7, g.context(), state));
  for (auto& s : seeds) {
    ASSERT_TRUE(store_record(s.data(), s.size())) << "a real record is read as it is";
    s.resize(s.size() - 8);  // the body: sealed by the target
  }
  maybe_save("store", seeds);
  int accepted = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    auto m = mutate(rng.pick(seeds), rng);
    accepted += store_record(m.data(), m.size());
  }
  std::printf("[fuzz] %d of %d mutated store records decoded\n", accepted, n);
  EXPECT_GT(accepted, n / 50) << "the mutations must reach the record parser";
  EXPECT_LT(accepted, n) << "some mutations must be rejected";
}

}  // namespace quiver::fuzz
