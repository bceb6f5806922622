// quiver_rogue: a hostile participant on Quiver's DDS topics, for the rogue suite (ctest label
// `rogue`). It joins a domain with the embedded loopback configuration (127.0.0.1, multicast off)
// and for --seconds publishes on every topic: random bytes, truncated and oversized samples, huge
// counts, counters at 2^64-1, other replicas' sequence ranges and dots (learned from their
// summaries and deltas), a forgery under a victim's name, lying summaries, pull floods and
// invented senders. It prints one JSON line of what it sent.
//
//   quiver_rogue --domain D [--seconds S] [--seed N]

#include <dds/dds.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/agents/transport/dds/dds_transport.h"
#include "quiver/agents/replica/security/keys.h"
#include "quiver/graph/codec.h"
#include "quiver/base/rng.h"
#include "forged_delta.h"
#include "quiver_wire.h"
#include "raw_sample.h"

namespace quiver::rogue {
namespace {

using agents::DdsTopic;
using agents::Sample;
using agents::Message;
using agents::PeerId;
using agents::Range;

constexpr PeerId kRogue{0x0bad0bad0bad0badULL, 1};

struct Victim {
  std::uint64_t next_seq = 1;  // one past the highest it has published, as its summaries say
  std::vector<std::uint8_t> payload;  // one of its real payloads, and its interval
  std::uint64_t lo = 0, hi = 0;
};

class Rogue {
 public:
  /// With `security`, the rogue is an authenticated member of the domain (it holds credentials of
  /// the agents' CA) rather than an outsider.
  Rogue(std::uint32_t domain, std::uint64_t seed, const std::optional<agents::security::DdsSecurityFiles>& security)
      : rng_(seed) {
    agents::DdsConfig cfg;
    cfg.domain = domain;
    const std::string xml = agents::loopback_config_xml(cfg);
    dom_ = dds_create_domain(domain, xml.c_str());
    if (dom_ < 0 && dom_ != DDS_RETCODE_PRECONDITION_NOT_MET) fail("dds_create_domain", dom_);
    dds_qos_t* pq = dds_create_qos();
    if (security)
      if (Status s = agents::set_security_qos(pq, *security); !s.ok()) {
        std::fprintf(stderr, "quiver_rogue: %s\n", s.error().to_string().c_str());
        std::exit(2);
      }
    pp_ = dds_create_participant(domain, pq, nullptr);
    dds_delete_qos(pq);
    if (pp_ < 0) fail("dds_create_participant", pp_);
    dds_qos_t* q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_MSECS(50));
    dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
    dds_qset_ignorelocal(q, DDS_IGNORELOCAL_PARTICIPANT);
    const dds_topic_descriptor_t* descs[] = {&quiver_wire_Summary_desc, &quiver_wire_Delta_desc, &quiver_wire_Pull_desc,
                                             &quiver_wire_StateChunk_desc, &quiver_wire_Bye_desc};
    for (std::size_t i = 0; i < agents::kDdsTopicCount; ++i) {
      const char* name = agents::topic_name(static_cast<DdsTopic>(i));
      topics_[i] = dds_create_topic(pp_, descs[i], name, nullptr, nullptr);
      if (topics_[i] < 0) fail("dds_create_topic", topics_[i]);
      writers_[i] = dds_create_writer(pp_, topics_[i], q, nullptr);
      if (writers_[i] < 0) fail("dds_create_writer", writers_[i]);
    }
    summaries_ = dds_create_reader(pp_, topics_[0], nullptr, nullptr);
    deltas_ = dds_create_reader(pp_, topics_[1], q, nullptr);
    dds_delete_qos(q);
    // Sertypes, from one well-formed sample of each type.
    for (std::size_t i = 0; i < agents::kDdsTopicCount; ++i) {
      auto valid = valid_sample(static_cast<DdsTopic>(i));
      types_[i] = probe_sertype(pp_, topics_[i], valid.get());
      if (types_[i] == nullptr) fail("probe_sertype", -1);
    }
  }
  // The domain goes too: its threads (decrypting, with security) must stop before exit() runs
  // OpenSSL's cleanup, or they crash in it.
  ~Rogue() {
    dds_delete(pp_);
    if (dom_ > 0) dds_delete(dom_);
  }

  void run(double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      learn();
      for (int i = 0; i < 20; ++i) attack();
      dds_sleepfor(DDS_MSECS(10));
    }
    std::map<std::string, std::uint64_t> out(sent_.begin(), sent_.end());
    nlohmann::json j;
    j["sent"] = out;
    j["victims"] = victims_.size();
    j["write_errors"] = write_errors_;
    std::printf("%s\n", j.dump().c_str());
  }

 private:
  [[noreturn]] static void fail(const char* what, dds_return_t rc) {
    std::fprintf(stderr, "quiver_rogue: %s: %s\n", what, rc < 0 ? dds_strretcode(rc) : "failed");
    std::exit(2);
  }

  static Sample sample(Message m, PeerId from = kRogue, PeerId to = {}) { return Sample{from, to, std::move(m)}; }
  // A well-formed typed sample of each topic (zeroed sequences are empty), for the sertype probe.
  static std::unique_ptr<void, void (*)(void*)> valid_sample(DdsTopic t) {
    const dds_topic_descriptor_t* descs[] = {&quiver_wire_Summary_desc, &quiver_wire_Delta_desc, &quiver_wire_Pull_desc,
                                             &quiver_wire_StateChunk_desc, &quiver_wire_Bye_desc};
    std::unique_ptr<void, void (*)(void*)> s(std::calloc(1, descs[static_cast<int>(t)]->m_size), std::free);
    if (t == DdsTopic::kSummary) static_cast<quiver_wire_Summary*>(s.get())->name = const_cast<char*>("rogue");
    return s;
  }

  void send(DdsTopic t, const std::vector<std::uint8_t>& bytes, const char* kind) {
    const auto i = static_cast<std::size_t>(t);
    if (write_raw(writers_[i], types_[i], bytes) != DDS_RETCODE_OK) ++write_errors_;
    ++sent_[kind];
  }
  void send(const Sample& e, const char* kind, int xcdr = 1, bool le = true) {
    send(agents::topic_of(e.message), agents::encode_cdr_sample(e, xcdr, le).bytes, kind);
  }

  // Learns the honest agents (and their sequence numbers) from their summaries and deltas.
  void learn() {
    void* samples[32] = {};
    dds_sample_info_t infos[32];
    int n = dds_take(summaries_, samples, infos, 32, 32);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* s = static_cast<const quiver_wire_Summary*>(samples[i]);
      const PeerId who{s->sender_agent, s->sender_incarnation};
      if (who == kRogue || who.agent < 0x10000) continue;  // ours and invented senders
      Victim& v = victims_[who];
      for (std::uint32_t r = 0; r < s->applied._length; ++r) {
        const auto& rr = s->applied._buffer[r];
        if (rr.replica.agent == who.agent && rr.replica.incarnation == who.incarnation)
          for (std::uint32_t k = 0; k < rr.ranges._length; ++k)
            v.next_seq = std::max(v.next_seq, rr.ranges._buffer[k].hi + 1);
      }
    }
    if (n > 0) dds_return_loan(summaries_, samples, n);
    for (auto& s : samples) s = nullptr;
    n = dds_take(deltas_, samples, infos, 32, 32);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* d = static_cast<const quiver_wire_Delta*>(samples[i]);
      const PeerId origin{d->origin.agent, d->origin.incarnation};
      auto it = victims_.find(origin);
      if (it == victims_.end() || d->payload._length == 0) continue;
      it->second.payload.assign(d->payload._buffer, d->payload._buffer + d->payload._length);
      it->second.lo = d->lo;
      it->second.hi = d->hi;
    }
    if (n > 0) dds_return_loan(deltas_, samples, n);
  }

  std::vector<std::uint8_t> random_bytes(std::size_t n) {
    std::vector<std::uint8_t> b(n);
    for (auto& x : b) x = static_cast<std::uint8_t>(rng_.below(256));
    return b;
  }

  void attack() {
    const auto topic = static_cast<DdsTopic>(rng_.below(agents::kDdsTopicCount));
    switch (rng_.below(12)) {
      case 0: {  // random bytes behind a valid header (so the RTPS layer delivers them)
        auto b = random_bytes(rng_.below(300));
        b.insert(b.begin(), {0x00, 0x01, 0x00, 0x00});
        send(topic, b, "random_bytes");
        break;
      }
      case 1: {  // a real-shaped sample, truncated
        auto b = agents::encode_cdr_sample(sample(agents::SummaryMsg{"rogue", false, {Range{kRogue, 1, 5}}})).bytes;
        b.resize(4 + rng_.below(b.size() - 4));
        send(DdsTopic::kSummary, b, "truncated");
        break;
      }
      case 2: {  // oversized: a big payload that does not decode, and a chunk over the limit
        if (rng_.chance(0.05)) {
          auto big = std::make_shared<const std::vector<std::uint8_t>>(random_bytes(std::size_t{8} << 20));
          send(sample(agents::DeltaMsg{kRogue, 1, 1, big}), "oversized");
        }
        break;
      }
      case 3: {  // huge counts
        auto chunk = std::make_shared<const std::vector<std::uint8_t>>(std::vector<std::uint8_t>{1, 2});
        send(sample(agents::StateMsg{rng_.next(), 0xfffffffe, 0xffffffff, {}, chunk}), "huge_counts");
        if (rng_.chance(0.02)) {
          agents::RangeList many;
          for (std::uint64_t k = 0; k < 100'000; ++k) many.push_back(Range{PeerId{k + 1, 1}, 1, 2});
          send(sample(agents::SummaryMsg{"rogue", false, many}), "huge_counts");
        }
        break;
      }
      case 4: {  // counters at 2^64-1, lo = 0, hi < lo
        const Range bad[] = {Range{kRogue, 1, UINT64_MAX}, Range{kRogue, 0, 3}, Range{kRogue, 9, 2}};
        const Range& r = bad[rng_.below(3)];
        send(sample(rng_.chance(0.5) ? Message(agents::SummaryMsg{"rogue", false, {r}})
                                        : Message(agents::PullMsg{1, {r}, {r}})),
             "bad_counters");
        break;
      }
      case 5:
      case 6:
      case 7:
        attack_victim();
        break;
      case 8: {  // lying summary: claims far more of every victim than exists
        agents::RangeList lie;
        for (const auto& [id, v] : victims_) lie.push_back(Range{id, 1, v.next_seq + 100'000});
        send(sample(agents::SummaryMsg{"liar", false, lie}), "lying_summary");
        break;
      }
      case 9: {  // pull flood: "send me everything", as the rogue and as invented peers
        const PeerId from = rng_.chance(0.5) ? kRogue : PeerId{0x100 + rng_.below(5000), 1};
        send(sample(agents::PullMsg{rng_.next(), {}, {}}, from), "pull_flood");
        break;
      }
      case 10: {  // invented senders
        send(sample(agents::SummaryMsg{"sybil", false, {}}, PeerId{0x100 + rng_.below(100'000), 1}), "sybils");
        break;
      }
      default: {  // other encodings of a bad sample
        send(sample(agents::SummaryMsg{"rogue", false, {Range{kRogue, 0, 0}}}), "bad_counters", 2, false);
        break;
      }
    }
  }

  // Other replicas' sequence ranges and dots.
  void attack_victim() {
    if (victims_.empty()) return;
    auto it = victims_.begin();
    std::advance(it, static_cast<long>(rng_.below(victims_.size())));
    const PeerId victim = it->first;
    Victim& v = it->second;
    switch (rng_.below(5)) {
      case 0: {  // an empty payload claiming the victim's next numbers
        graph::GraphDelta empty;
        empty.origin = victim;
        empty.seq_lo = v.next_seq;
        empty.seq_hi = v.next_seq + 1000;
        send(sample(agents::DeltaMsg{victim, empty.seq_lo, empty.seq_hi, bytes_of(empty)}), "claim_others_numbers");
        break;
      }
      case 1: {  // one of its real payloads replayed under other numbers
        if (v.payload.empty()) return;
        send(sample(agents::DeltaMsg{victim, v.hi + 1, v.hi + 500,
                                       std::make_shared<const std::vector<std::uint8_t>>(v.payload)}),
             "replay");
        break;
      }
      case 2: {  // a delta of ours carrying the victim's dots
        graph::GraphDelta d = node_delta(kRogue, 1, 1, graph::Dot{victim, 1'000'000 + rng_.below(1000)}, "stolen");
        send(sample(agents::DeltaMsg{kRogue, 1, 1, bytes_of(d)}), "others_dots");
        break;
      }
      case 3: {  // the same (origin, seq) as one it published, with another payload: equivocation
        if (v.payload.empty()) return;
        graph::GraphDelta d = node_delta(victim, v.lo, v.hi, graph::Dot{victim, 5'000'000 + rng_.below(1000)}, "other");
        send(sample(agents::DeltaMsg{victim, v.lo, v.hi, bytes_of(d)}, victim), "equivocation");
        break;
      }
      default: {  // a forgery under its name, far beyond its numbers, sent as if by it
        if (forged_.count(victim)) return;
        forged_[victim] = true;
        const std::uint64_t seq = v.next_seq + 10'000;
        graph::GraphDelta d = node_delta(victim, seq, seq, graph::Dot{victim, 9'000'000}, "forged_by_rogue");
        send(sample(agents::DeltaMsg{victim, seq, seq, bytes_of(d)}, victim), "forgery");
      }
    }
  }

  // A delta of `origin` over [lo, hi] creating one node whose id is `dot`.
  static graph::GraphDelta node_delta(PeerId origin, std::uint64_t lo, std::uint64_t hi, graph::Dot dot,
                                      const std::string& name) {
    return testing::forged_node_delta(origin, lo, hi, dot, "rogue", name + std::to_string(dot.counter));
  }
  static std::shared_ptr<const std::vector<std::uint8_t>> bytes_of(const graph::GraphDelta& d) {
    return testing::bytes_of(d);
  }

  Rng rng_;
  dds_entity_t pp_ = 0;
  dds_entity_t topics_[agents::kDdsTopicCount] = {};
  dds_entity_t writers_[agents::kDdsTopicCount] = {};
  const ddsi_sertype* types_[agents::kDdsTopicCount] = {};
  dds_entity_t summaries_ = 0, deltas_ = 0;
  std::map<PeerId, Victim> victims_;
  std::map<PeerId, bool> forged_;
  std::map<std::string, std::uint64_t> sent_;
  std::uint64_t write_errors_ = 0;
  dds_entity_t dom_ = 0;
};

}  // namespace
}  // namespace quiver::rogue

int main(int argc, char** argv) {
  CLI::App app{"quiver_rogue: a hostile participant on Quiver's DDS topics (loopback only), for the rogue suite"};
  std::uint32_t domain = 0;
  double seconds = 10;
  std::uint64_t seed = 1;
  app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 230))->required();
  app.add_option("--seconds", seconds, "how long to attack")->check(CLI::Range(0.1, 3600.0));
  app.add_option("--seed", seed, "seed of the attacks")->check(CLI::NonNegativeNumber);
  std::string security_dir, name = "rogue";
  app.add_option("--security", security_dir, "attack as an authenticated member: credentials of `quiver keys`");
  app.add_option("--name", name, "with --security: whose credentials")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::optional<quiver::agents::security::DdsSecurityFiles> files;
  if (!security_dir.empty()) {
    auto f = quiver::agents::security::agent_files(security_dir, name);
    if (!f.ok()) {
      std::fprintf(stderr, "quiver_rogue: --security: %s\n", f.error().to_string().c_str());
      return 2;
    }
    files = *f;
  }
  std::fprintf(stderr, "quiver_rogue: domain %u, %.1f s, seed %llu\n", domain, seconds,
               static_cast<unsigned long long>(seed));
  quiver::rogue::Rogue r(domain, seed, files);
  r.run(seconds);
  return 0;
}
