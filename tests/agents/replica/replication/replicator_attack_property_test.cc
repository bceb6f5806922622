// Randomized schedules of the rogue suite's attacks on the hand-driven network: three honest
// replicas churn while a forger injects, into a random subset of them, empty claims on a victim's
// next numbers, deltas carrying a victim's dots, equivocations of a victim's real intervals,
// forgeries far beyond a victim's numbers, lying summaries and invented senders. Frames are
// delivered in random order and some are lost while the attack lasts. Once it stops, every
// schedule must converge: the same digest at every replica.
//
// Each schedule prints its seed on failure; QUIVER_SEED=<seed> replays one exactly,
// QUIVER_SCHEDULES=<n> runs more.

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/graph/codec.h"
#include "quiver/base/rng.h"
#include "quiver/sim/workload.h"
#include "forged_delta.h"
#include "test_net.h"

namespace quiver::agents {
namespace {

using graph::GraphDelta;

const PeerId kRogue{0xbad, 1};

using testing::bytes_of;

GraphDelta one_node_delta(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, graph::Dot dot,
                          const std::string& name) {
  return testing::forged_node_delta(origin, lo, hi, dot, "rogue", name + std::to_string(dot.counter));
}

// What the forger has seen of a victim's deltas (it listens like any participant).
struct Victim {
  std::uint64_t lo = 0, hi = 0, next_seq = 1;
  bool forged = false;
};

struct Schedule {
  Schedule(std::uint64_t seed, bool gossip) : rng(seed) { opt.gossip = gossip; }

  Rng rng;
  ReplicatorOptions opt;
  Net net;
  std::map<PeerId, Victim> victims;
  sim::Churn churn;
  unsigned long long delivered = 0;
  bool storm = false;
  // Heartbeats of 3 replicas for 60 s are a few thousand samples; repairs add some hundreds.
  static constexpr unsigned long long kMaxQuietFrames = 200'000;

  void observe(const Packet& f) {
    auto e = decode_cdr_sample(f.sample.topic, f.sample.bytes);
    if (!e.ok()) return;
    if (const auto* d = std::get_if<DeltaMsg>(&e->message)) {
      if (d->origin == kRogue) return;
      Victim& v = victims[d->origin];
      if (d->hi + 1 > v.next_seq) {
        v.next_seq = d->hi + 1;
        v.lo = d->lo;
        v.hi = d->hi;
      }
    }
  }

  // Into a random non-empty subset of the replicas, as if DDS lost the forger's sample elsewhere.
  void inject(const PeerId& from, const Message& m) {
    const std::uint64_t mask = 1 + rng.below(7);
    for (int i = 0; i < 3; ++i) {
      if (!(mask & (1u << i))) continue;
      net.nodes[i].rep->on_sample(Sample{from, PeerId{}, m}, net.now);
    }
  }

  void attack() {
    if (victims.empty()) return;
    auto it = victims.begin();
    std::advance(it, static_cast<long>(rng.below(victims.size())));
    const PeerId victim = it->first;
    Victim& v = it->second;
    switch (rng.below(7)) {
      case 0: {
        GraphDelta empty;
        empty.origin = victim;
        empty.seq_lo = v.next_seq;
        empty.seq_hi = v.next_seq + rng.below(50);
        inject(kRogue, DeltaMsg{victim, empty.seq_lo, empty.seq_hi, bytes_of(empty)});
        break;
      }
      case 1: {
        GraphDelta d = one_node_delta(kRogue, 1, 1, graph::Dot{victim, 1'000'000 + rng.below(1000)}, "stolen");
        inject(kRogue, DeltaMsg{kRogue, 1, 1, bytes_of(d)});
        break;
      }
      case 2: {
        if (v.hi == 0) return;
        GraphDelta d = one_node_delta(victim, v.lo, v.hi, graph::Dot{victim, 5'000'000 + rng.below(1000)}, "other");
        inject(victim, DeltaMsg{victim, v.lo, v.hi, bytes_of(d)});
        break;
      }
      case 3: {
        if (v.forged) return;
        v.forged = true;
        const std::uint64_t seq = v.next_seq + 1 + rng.below(20);
        GraphDelta d = one_node_delta(victim, seq, seq, graph::Dot{victim, 9'000'000}, "forged");
        inject(victim, DeltaMsg{victim, seq, seq, bytes_of(d)});
        break;
      }
      case 4: {
        RangeList lie;
        for (const auto& [id, vv] : victims) lie.push_back(Range{id, 1, vv.next_seq + 100});
        inject(PeerId{0x1ee, 1}, SummaryMsg{"liar", false, lie});
        break;
      }
      case 5: {
        inject(PeerId{0x100 + rng.below(50), 1}, SummaryMsg{"sybil", false, {}});
        break;
      }
      default: {  // a forged interval covering the victim's next real numbers
        GraphDelta d = one_node_delta(victim, v.next_seq, v.next_seq + rng.below(5),
                                      graph::Dot{victim, 7'000'000 + rng.below(1000)}, "ahead");
        inject(victim, DeltaMsg{victim, d.seq_lo, d.seq_hi, bytes_of(d)});
      }
    }
  }

  // Delivers one sample in flight chosen at random; loses it with probability `loss`.
  void deliver_one(double loss) {
    const std::size_t k = rng.below(net.inflight.size());
    Packet f = std::move(net.inflight[k]);
    net.inflight.erase(net.inflight.begin() + static_cast<long>(k));
    observe(f);
    ++delivered;
    if (rng.chance(loss)) return;
    deliver_cdr_sample(*net.nodes[f.to].rep, f.sample.topic, f.sample.bytes, net.now);
  }

  void run() {
    for (int i = 0; i < 3; ++i) net.add(static_cast<std::uint64_t>(i + 1), opt);
    net.pump();
    const std::int64_t step = 10'000'000;  // 10 ms of virtual time
    for (int t = 0; t < 600; ++t) {        // 6 s of churn and attack
      net.now += step;
      for (auto& n : net.nodes) {
        if (rng.chance(0.3)) churn.step(*n.g, rng, net.now);
        n.rep->tick(net.now);
      }
      if (rng.chance(0.3)) attack();
      for (std::size_t k = net.inflight.size(); k > 0 && !net.inflight.empty(); --k) deliver_one(0.05);
    }
    // Quiet: no churn, no attack, no loss; 60 s of virtual time. The network must settle: a
    // version relayed for ever between honest replicas would be a storm that never ends.
    const unsigned long long before_quiet = delivered;
    for (int t = 0; t < 6000; ++t) {
      net.now += step;
      for (auto& n : net.nodes) n.rep->tick(net.now);
      while (!net.inflight.empty() && delivered - before_quiet < kMaxQuietFrames) deliver_one(0.0);
      if (delivered - before_quiet >= kMaxQuietFrames) {
        storm = true;
        return;
      }
    }
  }
};

std::uint64_t env_or(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v ? std::strtoull(v, nullptr, 10) : fallback;
}

// Both membership protocols: gossip and all-to-all (QUIVER_PROTOCOL=gossip or all-to-all
// replays one).
class ReplicatorAttackPropertyTest : public ::testing::TestWithParam<bool> {};

TEST_P(ReplicatorAttackPropertyTest, EveryScheduleConvergesAfterTheAttack) {
  const bool gossip = GetParam();
  const char* protocol = gossip ? "gossip" : "all-to-all";
  if (const char* only_protocol = std::getenv("QUIVER_PROTOCOL"); only_protocol && protocol != std::string(only_protocol))
    GTEST_SKIP() << "QUIVER_PROTOCOL=" << only_protocol;
  const std::uint64_t only = env_or("QUIVER_SEED", 0);
  const std::uint64_t count = only ? 1 : env_or("QUIVER_SCHEDULES", 200);
  const std::uint64_t base = 0x5eed'0000;
  int failures = 0;
  std::uint64_t equivocations = 0, divergences = 0;
  for (std::uint64_t k = 0; k < count && failures < 3; ++k) {
    const std::uint64_t seed = only ? only : base + k;
    Schedule s(seed, gossip);
    s.run();
    const auto digest = s.net.nodes[0].g->digest();
    bool same = true;
    for (auto& n : s.net.nodes) {
      same = same && n.g->digest() == digest;
      equivocations += n.rep->stats().equivocations;
      divergences += n.rep->stats().divergences;
    }
    if (s.storm) {
      ++failures;
      ADD_FAILURE() << protocol << " schedule with seed " << seed << ": the replicas kept sending after the attack stopped ("
                    << Schedule::kMaxQuietFrames << " frames in the quiet phase; replay: QUIVER_SEED=" << seed << ")";
      continue;
    }
    if (!same) {
      ++failures;
      std::string detail;
      for (auto& n : s.net.nodes)
        detail += " [" + std::to_string(n.g->node_count()) + " nodes, " + std::to_string(n.g->edge_count()) +
                  " edges, digest " + n.g->digest().hex() + ", synced " + (n.rep->synced() ? "yes" : "no") + "]";
      for (auto& n : s.net.nodes) {
        const auto& st = n.rep->stats();
        detail += "\n  " + n.g->replica().to_string() + ": pulls " + std::to_string(st.pulls_sent) + " timed out " +
                  std::to_string(st.pulls_timed_out) + " states " + std::to_string(st.states_applied) +
                  " throttled " + std::to_string(st.state_answers_throttled) + " suspects " +
                  std::to_string(st.suspects) + " divergences " + std::to_string(st.divergences) + " peers:";
        for (const auto& p : n.rep->peers())
          detail += " " + p.id.to_string() + (p.alive ? "" : "(gone)") + (p.suspect ? "(suspect)" : "");
        for (auto& o : s.net.nodes) {
          crdt::CausalContext lack = o.rep->applied().minus(n.rep->applied());
          lack.for_each_range([&](const PeerId& r, std::uint64_t a, std::uint64_t b) {
            detail += "\n    lacks " + r.to_string() + " [" + std::to_string(a) + "," + std::to_string(b) + "] that " +
                      o.g->replica().to_string() + " holds";
          });
        }
        if (std::getenv("QUIVER_TRACE"))
          for (const Error& e : n.errors) detail += "\n    " + e.message;
      }
      ADD_FAILURE() << protocol << " schedule with seed " << seed << " did not converge (replay: QUIVER_PROTOCOL="
                    << protocol << " QUIVER_SEED=" << seed << "):" << detail;
    }
  }
  std::printf("[attack, %s] %llu schedules from seed %llu: %llu equivocations seen, %llu divergences repaired\n",
              protocol, static_cast<unsigned long long>(count), static_cast<unsigned long long>(only ? only : base),
              static_cast<unsigned long long>(equivocations), static_cast<unsigned long long>(divergences));
  EXPECT_GT(equivocations, 0u) << "the attacks reached the replicas";
}

INSTANTIATE_TEST_SUITE_P(Protocols, ReplicatorAttackPropertyTest, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Gossip" : "AllToAll"; });

}  // namespace
}  // namespace quiver::agents
