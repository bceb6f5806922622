// Several agents in one process, each with its own Cyclone DDS domain instance (threads,
// sockets) on the loopback default configuration, each spinning on its own thread.

#include <gtest/gtest.h>

#include <sys/syscall.h>
#include <unistd.h>

#include <fstream>
#include <future>
#include <map>
#include <set>
#include <thread>

#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/base/rng.h"
#include "quiver/sim/workload.h"
#include "test_seed.h"

namespace quiver::agents {
namespace {

constexpr std::int64_t kMs = 1'000'000;

// Domain ids distinct per test so that nothing else on this machine meets these agents.
std::uint32_t test_domain(int index) { return 150 + static_cast<std::uint32_t>(index); }

struct Running {
  std::unique_ptr<DdsReplica> agent;
  std::thread thread;
  ~Running() {
    if (thread.joinable()) {
      agent->stop();
      thread.join();
    }
  }
  // Runs fn on the agent's thread and waits for its result.
  template <class F>
  auto call(F fn) -> decltype(fn(*agent)) {
    std::promise<decltype(fn(*agent))> done;
    auto fut = done.get_future();
    agent->post([&] {
      if constexpr (std::is_void_v<decltype(fn(*agent))>) {
        fn(*agent);
        done.set_value();
      } else {
        done.set_value(fn(*agent));
      }
    });
    return fut.get();
  }
};

// A replica of its own Cyclone domain instance on the loopback default configuration.
DdsReplicaOptions own_instance(const std::string& name, std::uint32_t domain) {
  DdsReplicaOptions o;
  o.name = name;
  o.dds.domain = domain;
  o.dds.own_domain_instance = true;
  return o;
}

std::vector<std::unique_ptr<Running>> start(int n, std::uint32_t domain, int loss_permille = 0,
                                            std::int64_t lease_ns = 1'000'000'000,
                                            std::int64_t heartbeat_ns = 50 * kMs) {
  std::vector<std::unique_ptr<Running>> out;
  for (int i = 0; i < n; ++i) {
    DdsReplicaOptions o = own_instance("agent" + std::to_string(i), domain);
    o.dds.xmit_loss_permille = loss_permille;
    o.dds.lease_ns = lease_ns;
    o.replicator.heartbeat_ns = heartbeat_ns;
    auto a = DdsReplica::create(o);
    EXPECT_TRUE(a.ok()) << a.error().to_string();
    if (!a.ok()) return {};
    auto r = std::make_unique<Running>();
    r->agent = std::move(*a);
    DdsReplica* raw = r->agent.get();
    r->thread = std::thread([raw] { raw->spin(); });
    out.push_back(std::move(r));
  }
  return out;
}

// Polls until every agent reports the same digest (and at least `min_nodes` nodes), or times out.
bool converge(std::vector<std::unique_ptr<Running>>& agents, std::int64_t timeout_ms, std::size_t min_nodes = 0) {
  const std::int64_t end = monotonic_ns() + timeout_ms * kMs;
  while (monotonic_ns() < end) {
    std::vector<Digest128> d;
    bool enough = true;
    for (auto& r : agents) {
      d.push_back(r->call([](DdsReplica& a) { return a.graph().digest(); }));
      enough = enough && r->call([](DdsReplica& a) { return a.graph().node_count(); }) >= min_nodes;
    }
    bool same = enough;
    for (const auto& x : d) same = same && x == d[0];
    if (same) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void churn(Running& r, Rng& rng, int txns, std::int64_t t0) {
  sim::Churn work;
  r.call([&](DdsReplica& a) {
    for (int i = 0; i < txns; ++i) work.step(a.graph(), rng, t0 + i);
  });
}

// Every field the protocol relies on survives the mapping to DDS samples and back: the digest of
// a summary (without it no replica over DDS could find a divergence) and a pull's whole-state and
// as-state requests, in both CDR versions and byte orders.
TEST(DdsInProcessTest, SummaryDigestAndPullFlagsTravelInSamples) {
  const PeerId a{11, 1}, b{12, 1};
  const RangeList applied{Range{a, 1, 7}, Range{b, 3, 9}};
  for (int xcdr : {1, 2})
    for (bool le : {true, false}) {
      SummaryMsg sm{"agent a", true, applied};
      sm.digest = 0x0123456789abcdefULL;
      sm.beat = Beat::kRelayedAck;
      sm.life = 3;
      sm.set_hash = 0xfeed;
      sm.count = 42;
      sm.your_seq = 7;
      sm.covered = 0xbeef;
      sm.subject = PeerId{9, 2};
      sm.rumors = {Rumor{PeerId{5, 1}, 4, Liveness::kSuspect}, Rumor{PeerId{6, 1}, 0, Liveness::kDead}};
      auto s = decode_cdr_sample(DdsTopic::kSummary, encode_cdr_sample(Sample{a, b, sm}, xcdr, le).bytes);
      ASSERT_TRUE(s.ok()) << s.error().to_string();
      const auto& got = std::get<SummaryMsg>(s->message);
      EXPECT_EQ(s->to, b);
      EXPECT_EQ(got.beat, Beat::kRelayedAck);
      EXPECT_EQ(got.life, 3u);
      EXPECT_EQ(got.set_hash, 0xfeedu);
      EXPECT_EQ(got.count, 42u);
      EXPECT_EQ(got.your_seq, 7u);
      EXPECT_EQ(got.covered, 0xbeefu);
      EXPECT_EQ(got.subject, (PeerId{9, 2}));
      EXPECT_EQ(got.rumors, sm.rumors);
      EXPECT_EQ(got.digest, sm.digest);
      EXPECT_EQ(got.name, "agent a");
      EXPECT_TRUE(got.observer);
      EXPECT_EQ(got.applied, applied);
      for (bool whole : {false, true})
        for (bool as_state : {false, true}) {
          PullMsg pm{77, applied, {Range{a, 2, 2}}, whole, as_state};
          auto p = decode_cdr_sample(DdsTopic::kPull, encode_cdr_sample(Sample{a, b, pm}, xcdr, le).bytes);
          ASSERT_TRUE(p.ok()) << p.error().to_string();
          const auto& gp = std::get<PullMsg>(p->message);
          EXPECT_EQ(gp.request, 77u);
          EXPECT_EQ(gp.whole_state, whole);
          EXPECT_EQ(gp.as_state, as_state);
          EXPECT_EQ(gp.applied, applied);
          EXPECT_EQ(gp.context, (RangeList{Range{a, 2, 2}}));
          EXPECT_EQ(p->to, b);
        }
    }
}

// DDS delivers every sample to every reader; a beat addressed to one replica must still reach
// only that one's owner thread (the readers' topic filter drops it elsewhere), a beat to nobody
// in particular reaches all, and each transport learns the others' replica ids from discovery.
TEST(DdsInProcessTest, AddressedBeatsReachOnlyTheirAddresseeAndDiscoveryNamesThePeers) {
  const PeerId ids[3] = {PeerId{0xa1, 1}, PeerId{0xb2, 1}, PeerId{0xc3, 1}};
  const std::string names[3] = {"planner", "speech", "viewer"};
  std::vector<std::unique_ptr<DdsTransport>> t;
  for (int i = 0; i < 3; ++i) {
    DdsConfig c;
    c.domain = test_domain(9);
    c.own_domain_instance = true;
    c.name = names[i];
    c.observer = i == 2;
    auto made = DdsTransport::create(ids[i], c);
    ASSERT_TRUE(made.ok()) << made.error().to_string();
    t.push_back(std::move(*made));
  }
  std::vector<std::map<PeerId, PeerCard>> introduced(3);
  std::vector<std::vector<Sample>> got(3);
  auto pump = [&](std::int64_t ms) {
    const std::int64_t end = monotonic_ns() + ms * kMs;
    while (monotonic_ns() < end)
      for (int i = 0; i < 3; ++i) {
        t[i]->wait(2 * kMs);
        t[i]->drain([&](const Sample& s) { got[i].push_back(s); }, [](const PeerId&, bool) {});
        for (const PeerCard& p : t[i]->take_new_peers()) introduced[i][p.id] = p;
      }
  };
  // Discovery first: every transport names the two others, never itself.
  const std::int64_t end = monotonic_ns() + 10'000 * kMs;
  while (monotonic_ns() < end && !(introduced[0].size() == 2 && introduced[1].size() == 2 && introduced[2].size() == 2)) {
    pump(20);
    for (auto& tr : t) (void)tr->take_new_match();
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(introduced[i].size(), 2u) << "transport " << i;
    EXPECT_EQ(introduced[i].count(ids[i]), 0u);
    // Each card carries the name and role its participant announced.
    for (int j = 0; j < 3; ++j) {
      if (j == i) continue;
      auto it = introduced[i].find(ids[j]);
      ASSERT_NE(it, introduced[i].end()) << "transport " << i << " never heard of " << names[j];
      EXPECT_EQ(it->second.name, names[j]);
      EXPECT_EQ(it->second.observer, j == 2);
    }
  }
  pump(200);  // the readers and writers match too
  for (auto& g : got) g.clear();
  // A beat to b, repeated (best effort), and one to everyone.
  SummaryMsg to_b;
  to_b.name = "a";
  to_b.beat = Beat::kPing;
  SummaryMsg to_all = to_b;
  to_all.beat = Beat::kHello;
  for (int k = 0; k < 5; ++k) {
    t[0]->send(Sample{ids[0], ids[1], to_b});
    pump(20);
  }
  t[0]->send(Sample{ids[0], PeerId{}, to_all});
  pump(300);
  auto count = [&](int who, Beat b) {
    int n = 0;
    for (const Sample& s : got[who])
      if (const auto* m = std::get_if<SummaryMsg>(&s.message); m != nullptr && m->beat == b) ++n;
    return n;
  };
  EXPECT_GE(count(1, Beat::kPing), 1) << "the addressee got none of the beats addressed to it";
  EXPECT_EQ(count(2, Beat::kPing), 0) << "a beat addressed to b reached c's thread";
  EXPECT_EQ(count(1, Beat::kHello), 1);
  EXPECT_EQ(count(2, Beat::kHello), 1);
  for (const Sample& s : got[2]) EXPECT_TRUE(s.to.is_null() || s.to == ids[2]);
}

TEST(DdsInProcessTest, TwoAgentsReplicate) {
  auto agents = start(2, test_domain(0));
  ASSERT_EQ(agents.size(), 2u);
  agents[0]->call([](DdsReplica& a) {
    auto tx = a.graph().begin();
    ASSERT_TRUE(tx.create_node("robot", "robot", {{graph::Symbol("battery"), graph::Value(0.5)}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  });
  ASSERT_TRUE(converge(agents, 5000, 1));
  double b = agents[1]->call([](DdsReplica& a) {
    auto id = a.graph().find_node("robot");
    return id ? a.graph().get<double>(*id, "battery").value_or(-1) : -2.0;
  });
  EXPECT_EQ(b, 0.5);
}

TEST(DdsInProcessTest, AgentCutOffByDeafMuteCatchesUpAfterHeal) {
  const auto seed = quiver::testing::base_seed("DdsInProcessTest.AgentCutOffByDeafMuteCatchesUpAfterHeal", 5);
  Rng rng(seed);
  auto agents = start(4, test_domain(1));
  ASSERT_EQ(agents.size(), 4u);
  churn(*agents[0], rng, 5, 0);
  ASSERT_TRUE(converge(agents, 5000));
  // Cut agent 3 off entirely; the others keep writing.
  agents[3]->call([](DdsReplica& a) { ASSERT_TRUE(a.transport().set_deafmute(true, true, -1).ok()); });
  for (int round = 0; round < 5; ++round)
    for (int i = 0; i < 3; ++i) churn(*agents[i], rng, 4, 1000 * round);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  auto d_cut = agents[3]->call([](DdsReplica& a) { return a.graph().digest(); });
  auto d_main = agents[0]->call([](DdsReplica& a) { return a.graph().digest(); });
  EXPECT_NE(d_cut, d_main) << "the cut-off agent saw nothing";
  churn(*agents[3], rng, 4, 99999);  // and it changes things on its own side
  agents[3]->call([](DdsReplica& a) { ASSERT_TRUE(a.transport().set_deafmute(false, false, -1).ok()); });
  EXPECT_TRUE(converge(agents, 15000)) << "seed " << seed;
}

// A lease of 5 s or more paces Cyclone for many processes on one host (slower heartbeats, one
// port, 64 KiB datagrams on loopback): Cyclone accepts that configuration, and agents on it still
// replicate through 10% packet loss.
TEST(DdsInProcessTest, TheManyProcessesPaceReplicatesThroughLoss) {
  DdsConfig few, many;
  many.lease_ns = kManyProcessesLeaseNs;
  const std::string few_xml = loopback_config_xml(few), many_xml = loopback_config_xml(many);
  for (const char* part : {"<HeartbeatInterval", "<UnicastDataOffset>10", "<MaxMessageSize>65000B"}) {
    EXPECT_EQ(few_xml.find(part), std::string::npos) << part;
    EXPECT_NE(many_xml.find(part), std::string::npos) << part;
  }
  const auto seed = quiver::testing::base_seed("DdsInProcessTest.TheManyProcessesPaceReplicatesThroughLoss", 7);
  Rng rng(seed);
  auto agents = start(3, test_domain(3), /*loss_permille=*/100, /*lease_ns=*/10'000'000'000);
  ASSERT_EQ(agents.size(), 3u);
  for (int round = 0; round < 10; ++round)
    for (auto& a : agents) churn(*a, rng, 3, 100 * round);
  EXPECT_TRUE(converge(agents, 20000)) << "seed " << seed;
}

// The voluntary context switches of one thread of this process so far (its wakeups).
long thread_wakeups(pid_t tid) {
  std::ifstream f("/proc/self/task/" + std::to_string(tid) + "/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("voluntary_ctxt_switches:", 0) == 0) return std::stol(line.substr(24));
  return -1;
}

// A replica that hosts no agent (an observer, a benchmark's member, a program that only reads
// its graph) stays at the quiet pace while deltas arrive: 20 changes in a second wake it about
// 20 times plus its 10 quiet rounds and the peer's beats, where the busy pace of 10 ms would
// wake it more than 100 times (100 processes on two cores are what that costs).
TEST(DdsInProcessTest, AReplicaWithoutAnAgentStaysQuietWhileDeltasArrive) {
  // The default heartbeat period (100 ms): the peer's beats are part of what wakes the replica.
  auto agents = start(2, test_domain(5), 0, 1'000'000'000, ReplicatorOptions{}.heartbeat_ns);
  ASSERT_EQ(agents.size(), 2u);
  graph::NodeId node;
  agents[0]->call([&](DdsReplica& a) {
    auto tx = a.graph().begin();
    node = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.commit().ok());
  });
  ASSERT_TRUE(converge(agents, 5000, 1));
  const pid_t tid = agents[1]->call([](DdsReplica&) { return static_cast<pid_t>(syscall(SYS_gettid)); });
  std::this_thread::sleep_for(std::chrono::milliseconds(700));  // past quiet_after_ns
  const long before = thread_wakeups(tid);
  for (int i = 0; i < 20; ++i) {
    agents[0]->call([&](DdsReplica& a) {
      auto tx = a.graph().begin();
      ASSERT_TRUE(tx.set(node, graph::Symbol("seq"), graph::Value(static_cast<std::int64_t>(i))).ok());
      ASSERT_TRUE(tx.commit().ok());
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const long woke = thread_wakeups(tid) - before;
  ASSERT_GE(before, 0) << "no /proc/self/task/" << tid << "/status";
  const std::int64_t seen = agents[1]->call([&](DdsReplica& a) { return a.graph().get<std::int64_t>(node, "seq").value_or(-1); });
  EXPECT_EQ(seen, 19) << "the 20 changes did not all arrive";
  EXPECT_LT(woke, 80) << "the replica woke " << woke << " times in the second its 20 changes arrived";
  EXPECT_GE(woke, 10) << "the count of wakeups is not the replica thread's";
}

// An idle replica waiting in spin_until() wakes at its quiet pace (10 rounds a second), not also
// for a look at its predicate in between (it looked every 50 ms: 20 wakeups a second, which 100
// benchmark members waiting for their next phase paid at once).
TEST(DdsInProcessTest, AnIdleReplicaInSpinUntilWakesAtItsQuietPace) {
  const DdsReplicaOptions o = own_instance("waiting", test_domain(6));
  auto a = DdsReplica::create(o);
  ASSERT_TRUE(a.ok()) << a.error().to_string();
  DdsReplica& r = **a;
  r.spin_for(o.quiet_after_ns + 200 * kMs);
  const pid_t tid = static_cast<pid_t>(syscall(SYS_gettid));
  const long before = thread_wakeups(tid);
  ASSERT_GE(before, 0) << "no /proc/self/task/" << tid << "/status";
  int looks = 0;
  EXPECT_FALSE(r.spin_until([&] { return ++looks < 0; }, 2'000'000'000));
  const long woke = thread_wakeups(tid) - before;
  EXPECT_LT(woke, 32) << "an idle replica woke " << woke << " times in 2 s of spin_until()";
  EXPECT_GE(looks, 10) << "spin_until() looked at its predicate " << looks << " times in 2 s";
}

TEST(DdsInProcessTest, ConvergesDespiteTwentyPercentPacketLoss) {
  const auto seed = quiver::testing::base_seed("DdsInProcessTest.ConvergesDespiteTwentyPercentPacketLoss", 6);
  Rng rng(seed);
  auto agents = start(3, test_domain(2), /*loss_permille=*/200);
  ASSERT_EQ(agents.size(), 3u);
  for (int round = 0; round < 10; ++round)
    for (auto& a : agents) churn(*a, rng, 3, 100 * round);
  EXPECT_TRUE(converge(agents, 20000)) << "seed " << seed;
}

}  // namespace
}  // namespace quiver::agents

namespace quiver::agents {
namespace {

// Defect 10: a second agent in one process asking for another configuration of the same
// domain used to get the first one's silently; it is refused, naming the domain.
TEST(DdsInProcessTest, ASecondConfigurationOfOneDomainIsRefused) {
  DdsReplicaOptions a;
  a.name = "first";
  a.dds.domain = test_domain(9);
  auto first = DdsReplica::create(a);
  ASSERT_TRUE(first.ok()) << first.error().to_string();
  DdsReplicaOptions b = a;
  b.name = "second";
  b.dds.lease_ns = 3'000'000'000;  // another configuration of the same domain
  auto second = DdsReplica::create(b);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(second.error().message.find("domain " + std::to_string(test_domain(9))), std::string::npos)
      << second.error().message;
  DdsReplicaOptions c = a;
  c.name = "third";  // the same configuration is shared
  EXPECT_TRUE(DdsReplica::create(c).ok());
}

}  // namespace
}  // namespace quiver::agents
