// PeerTable: the replicator's peer table (peer_table.h): map order and lookups, records that
// never move, details made on demand and trimmed to a bound, and the bytes it reports.
#include "quiver/agents/replica/replication/peer_table.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "quiver/base/hash.h"
#include "test_net.h"

namespace quiver::agents {
namespace {

PeerId id(std::uint64_t agent, std::uint64_t incarnation = 1) { return PeerId{agent, incarnation}; }

TEST(PeerTableTest, KeepsPeersInIdOrderAsTheMapItReplacedDid) {
  const unsigned seed = 22;
  std::printf("seed %u\n", seed);
  std::mt19937_64 rng(seed);
  PeerTable t;
  std::set<PeerId> model;
  for (int i = 0; i < 3000; ++i) {
    const PeerId p = id(rng() % 500, rng() % 3);
    if (rng() % 3 == 0) {
      auto it = t.find(p);
      ASSERT_EQ(it != t.end(), model.count(p) == 1) << "step " << i;
      if (it != t.end()) t.erase(it);
      model.erase(p);
    } else {
      auto [it, added] = t.try_emplace(p);
      ASSERT_EQ(added, model.insert(p).second) << "step " << i;
      ASSERT_EQ(it->first, p);
    }
  }
  ASSERT_EQ(t.size(), model.size());
  auto m = model.begin();
  for (auto&& [pid, rec] : t) {
    ASSERT_EQ(pid, *m);
    EXPECT_EQ(rec.id, *m);
    ++m;
  }
  // upper_bound: the first peer after an id, present or not.
  for (std::uint64_t a = 0; a < 510; a += 7) {
    auto want = model.upper_bound(id(a));
    auto got = t.upper_bound(id(a));
    ASSERT_EQ(got == t.end(), want == model.end()) << a;
    if (want != model.end()) EXPECT_EQ(got->first, *want) << a;
  }
}

TEST(PeerTableTest, ARecordStaysWhereItIsWhateverIsAddedOrErased) {
  PeerTable t;
  PeerRecord& first = t[id(1001)];
  first.your_seq = 7;
  for (std::uint64_t a = 0; a < 2000; ++a) t[id(a * 3 + 1)].life = static_cast<std::uint32_t>(a);
  for (auto it = t.begin(); it != t.end();) it = it->first.agent % 2 == 0 ? t.erase(it) : ++it;
  EXPECT_EQ(&first, &t[id(1001)]);
  EXPECT_EQ(first.your_seq, 7u);
  EXPECT_EQ(t.count(id(1001)), 1u);
  EXPECT_EQ(t.count(id(4)), 0u);  // 4 = 1 * 3 + 1, even: erased
}

TEST(PeerTableTest, ADetailIsMadeOnDemandAndTheLeastRecentlyUsedThatMayGoAreTrimmed) {
  PeerTable t;
  for (std::uint64_t a = 1; a <= 40; ++a) t[id(a)];
  // Reading makes nothing.
  EXPECT_EQ(t.seen(t[id(3)]).report_ns, -1);
  EXPECT_TRUE(t.details().empty());
  for (std::uint64_t a = 1; a <= 40; ++a) t.detail(t[id(a)], static_cast<std::int64_t>(a)).hash = a;
  t.detail(t[id(2)], 100).holds.push_back({});  // used last, but not pinned
  ASSERT_EQ(t.details().size(), 40u);
  // Pinned: every peer whose id is a multiple of 10.
  t.trim_details(8, [](const PeerId& p, const PeerDetail&) { return p.agent % 10 == 0; });
  ASSERT_EQ(t.details().size(), 8u);
  std::set<std::uint64_t> kept;
  for (const auto& [p, d] : t.details()) kept.insert(p.agent);
  // 10, 20, 30, 40 pinned; then the most recently used: 2 (at 100), 39, 38, 37.
  EXPECT_EQ(kept, (std::set<std::uint64_t>{2, 10, 20, 30, 37, 38, 39, 40}));
  EXPECT_EQ(t.seen(t[id(39)]).hash, 39u);
  EXPECT_EQ(t.seen(t[id(5)]).hash, 0u);  // trimmed: back to the default
  // Pinned ones stay beyond the bound.
  t.trim_details(2, [](const PeerId& p, const PeerDetail&) { return p.agent % 10 == 0; });
  EXPECT_EQ(t.details().size(), 4u);
  // Erasing a peer erases its detail.
  t.erase(t.find(id(10)));
  EXPECT_EQ(t.details().count(id(10)), 0u);
}

TEST(PeerTableTest, AThousandPeersTakeAboutThirtyFourBytesEach) {
  PeerTable t;
  const std::size_t empty = t.memory_bytes();
  for (std::uint64_t a = 0; a < 1000; ++a) t[id(a * 7919)];
  const std::size_t bytes = t.memory_bytes() - empty;
  std::printf("1000 peers: %zu bytes\n", bytes);
  EXPECT_GE(bytes, 1000 * (sizeof(PeerRecord) + 2));
  EXPECT_LE(bytes, 1000 * (sizeof(PeerRecord) + 4) + 1024);
  // A detail costs what it holds (and its map node).
  t.detail(t[id(0)], 0).name = std::string(100, 'n');
  EXPECT_GE(t.memory_bytes() - empty - bytes, sizeof(PeerDetail) + 100);
}

// A replica among 40 under gossip keeps a detail for few of them, yet every rule that needs every
// peer still works: a claim is acknowledged by all (their records' your_seq) and a hand-over
// completes (a replica offering its set keeps every report until it leaves).
TEST(PeerTableTest, AmongFortyAReplicaKeepsFewDetailsYetAClaimIsAcknowledgedAndAHandOverCompletes) {
  Net net;
  ReplicatorOptions opt;
  opt.gossip = true;
  constexpr int kN = 40;
  std::vector<PeerCard> cards;
  for (int i = 0; i < kN; ++i) {
    opt.name = "member" + std::to_string(i);
    net.add(fnv1a64(opt.name), opt);
    cards.push_back(PeerCard{net.nodes[i].g->replica(), opt.name, false});
  }
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j)
      if (i != j) net.nodes[i].rep->introduce(cards[j]);
  for (int i = 0; i < kN; ++i) add_node(*net.nodes[i].g, "n" + std::to_string(i));
  net.advance(3'000'000'000, 300);
  for (int i = 1; i < kN; ++i) ASSERT_EQ(net.nodes[i].g->digest(), net.nodes[0].g->digest()) << i;
  Replicator& r = *net.nodes[0].rep;
  const auto with_detail = [&r] {
    std::size_t n = 0;
    for (const PeerInfo& p : r.peers()) n += p.last_heard_ns != 0 ? 1 : 0;
    return n;
  };
  ASSERT_EQ(r.peers().size(), static_cast<std::size_t>(kN - 1));
  EXPECT_LE(with_detail(), 20u) << "details are kept for the peers dealt with most recently only";
  // Every peer is still named: by its detail, or the name cache (32), or not at all beyond both.
  std::size_t named = 0;
  for (const PeerInfo& p : r.peers()) named += p.name.empty() ? 0 : 1;
  EXPECT_GE(named, 32u);
  // A claim's acknowledgements come from every live peer.
  add_node(*net.nodes[0].g, "claimed");
  const std::uint64_t seq = r.last_seq();
  r.want_acks(seq);
  net.advance(1'000'000'000, 100);
  EXPECT_TRUE(r.all_peers_hold(net.nodes[0].g->replica(), seq));
  // A hand-over: every peer holds what this replica holds, and it can tell.
  add_node(*net.nodes[0].g, "last words");
  r.offer_all();
  bool held = false;
  for (int k = 0; k < 50 && !held; ++k) {
    net.advance(100'000'000, 10);
    held = r.peers_hold_all();
  }
  EXPECT_TRUE(held) << "the hand-over never saw every peer hold this replica's set";
  EXPECT_GT(with_detail(), 30u) << "a replica handing over keeps every report";
}

}  // namespace
}  // namespace quiver::agents
