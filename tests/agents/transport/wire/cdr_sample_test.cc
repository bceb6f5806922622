// The simulator carries the bytes DDS ships: for a sample of every topic, what a Cyclone DDS
// writer serializes (taken back from a reader as its serdata, dds_takecdr) equals, byte for byte,
// encode_cdr_sample() of the same message; and decode_cdr_sample() gives the message back.

#include <gtest/gtest.h>

#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>

#include <chrono>
#include <thread>

#include "quiver/agents/transport/dds/dds_transport.h"
#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"
#include "quiver_wire.h"

namespace quiver::agents {
namespace {

// A gossip beat's size does not depend on how many replicas there are (docs/protocol.md gives
// the formula): a fixed part, the name (sent to peers that do not know it yet) and 32 bytes per
// piggybacked rumor.
TEST(CdrSampleTest, AGossipBeatHasAConstantSize) {
  auto size_of = [](const std::string& name, std::size_t rumors) {
    SummaryMsg m;
    m.name = name;
    m.beat = Beat::kPing;
    m.life = 1;
    m.set_hash = 0x1234;
    m.count = 1'000'000;
    m.your_seq = 77;
    m.rumors.assign(rumors, Rumor{PeerId{5, 1}, 2, Liveness::kSuspect});
    return encode_cdr_sample(Sample{PeerId{1, 1}, PeerId{2, 1}, m}).bytes.size();
  };
  const std::size_t bare = size_of("", 0);
  std::printf("[beat] bare %zu bytes, name 'agent17' %zu, 6 rumors %zu\n", bare, size_of("agent17", 0), size_of("", 6));
  EXPECT_EQ(bare, 120u);
  EXPECT_EQ(size_of("agent17", 0), bare + 8);
  EXPECT_EQ(size_of("", 6), bare + 6 * 32);
}

// A gateway's hold answer keeps its role, subject and number through the encoding.
TEST(CdrSampleTest, AHoldAnswerFromAGatewayKeepsItsRoleSubjectAndNumber) {
  for (bool observer : {false, true}) {
    SummaryMsg m;
    m.beat = Beat::kHolds;
    m.gateway = true;
    m.observer = observer;
    m.subject = PeerId{9, 4};
    m.subject_seq = 123456789;
    auto back = decode_cdr_sample(DdsTopic::kSummary, encode_cdr_sample(Sample{PeerId{1, 1}, PeerId{2, 1}, m}).bytes);
    ASSERT_TRUE(back.ok()) << back.error().to_string();
    const auto& got = std::get<SummaryMsg>(back->message);
    EXPECT_EQ(got.beat, Beat::kHolds);
    EXPECT_TRUE(got.gateway);
    EXPECT_EQ(got.observer, observer);
    EXPECT_EQ(got.subject, (PeerId{9, 4}));
    EXPECT_EQ(got.subject_seq, 123456789u);
  }
}

std::vector<Sample> one_of_each(const PeerId& a, const PeerId& b) {
  graph::Graph g(a);
  std::vector<std::vector<std::uint8_t>> deltas;
  g.set_delta_sink([&](const graph::GraphDelta& d) { deltas.push_back(graph::encode(d)); });
  auto tx = g.begin();
  (void)tx.create_node("mug", "mug", {{graph::Symbol("colour"), graph::Value("red")}});
  (void)tx.commit();
  auto bytes = [](std::vector<std::uint8_t> v) { return std::make_shared<const std::vector<std::uint8_t>>(std::move(v)); };
  const RangeList applied{Range{a, 1, 7}, Range{b, 3, 9}, Range{b, 12, 12}};
  return {
      Sample{a, PeerId{}, SummaryMsg{"writer", false, applied, 0x0123456789abcdefULL}},
      Sample{a, PeerId{}, DeltaMsg{a, 1, 1, bytes(deltas.at(0)), bytes({1, 2, 3, 4, 5})}},
      Sample{a, b, PullMsg{77, applied, {Range{a, 2, 2}}, true, false}},
      Sample{a, b, StateMsg{77, 1, 3, applied, bytes(graph::encode(g.state()))}},
      Sample{a, PeerId{}, ByeMsg{}},
  };
}

const dds_topic_descriptor_t* descriptor(DdsTopic t) {
  static const dds_topic_descriptor_t* kDescs[] = {&quiver_wire_Summary_desc, &quiver_wire_Delta_desc,
                                                   &quiver_wire_Pull_desc, &quiver_wire_StateChunk_desc,
                                                   &quiver_wire_Bye_desc};
  return kDescs[static_cast<int>(t)];
}

TEST(CdrSampleTest, TheSimulatorsBytesAreTheBytesADdsWriterShips) {
  const PeerId a{0xa11ce, 1}, b{0xb0b, 1};
  DdsConfig cfg;
  cfg.domain = 151;
  auto t = DdsTransport::create(a, cfg);
  ASSERT_TRUE(t.ok()) << t.error().to_string();
  // A plain participant of the same (loopback) domain instance reads what the transport writes,
  // as its serialized form.
  dds_entity_t pp = dds_create_participant(cfg.domain, nullptr, nullptr);
  ASSERT_GT(pp, 0);
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
  dds_qos_t* be = dds_create_qos();
  dds_qset_reliability(be, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(be, DDS_HISTORY_KEEP_ALL, 0);
  const auto samples = one_of_each(a, b);
  for (const Sample& s : samples) {
    const DdsTopic topic = topic_of(s.message);
    dds_entity_t tp = dds_create_topic(pp, descriptor(topic), topic_name(topic), nullptr, nullptr);
    ASSERT_GT(tp, 0) << topic_name(topic);
    // Summaries (beats) are written best effort: a reliable reader would not match their writer.
    dds_entity_t rd = dds_create_reader(pp, tp, topic == DdsTopic::kSummary ? be : q, nullptr);
    ASSERT_GT(rd, 0);
    // Wait until the transport's writer matched this reader, then write through the transport.
    for (int i = 0; i < 400; ++i) {
      dds_subscription_matched_status_t st{};
      dds_get_subscription_matched_status(rd, &st);
      if (st.current_count > 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    (*t)->send(s);
    ddsi_serdata* sd = nullptr;
    dds_sample_info_t info;
    int n = 0;
    for (int i = 0; i < 400 && n <= 0; ++i) {
      n = dds_takecdr(rd, &sd, 1, &info, 0);
      if (n <= 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_EQ(n, 1) << "no " << topic_name(topic) << " sample arrived";
    std::vector<std::uint8_t> shipped(ddsi_serdata_size(sd));
    ddsi_serdata_to_ser(sd, 0, shipped.size(), shipped.data());
    ddsi_serdata_unref(sd);
    const CdrSample ours = encode_cdr_sample(s);
    EXPECT_EQ(ours.topic, topic);
    EXPECT_EQ(ours.bytes, shipped) << topic_name(topic) << ": " << ours.bytes.size() << " bytes encoded, "
                                   << shipped.size() << " shipped";
    auto back = decode_cdr_sample(topic, shipped);
    ASSERT_TRUE(back.ok()) << back.error().to_string();
    EXPECT_EQ(back->from, s.from);
    EXPECT_EQ(back->message.index(), s.message.index());
    dds_delete(rd);
    dds_delete(tp);
  }
  dds_delete_qos(q);
  dds_delete_qos(be);
  dds_delete(pp);
}

}  // namespace
}  // namespace quiver::agents
