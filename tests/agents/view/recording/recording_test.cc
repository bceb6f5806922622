// The .qrec file, the graph recorder and the history: what is recorded replays to the recorded
// replica's exact state, files stay bounded, and damage is reported with where it is.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "graph_test_util.h"
#include "quiver/agents/view/recording/graph_recorder.h"
#include "quiver/agents/view/recording/history.h"
#include "quiver/agents/view/recording/record_file.h"

namespace quiver::agents::recording {
namespace {

using graph::testing::Peer;
namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("quiver_recording_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

// A writer peer makes changes; an observer graph merges them under a recorder.
struct Rig {
  Peer writer{7};
  graph::Graph observer{graph::ReplicaId{9, 1}};
  std::int64_t now = 0;
  std::vector<RecordedChange> changes;
  std::unique_ptr<GraphRecorder> recorder;

  void start() {
    recorder = std::make_unique<GraphRecorder>(
        observer, [this] { return now; },
        [](const graph::ReplicaId& r) { return r.agent == 7 ? "writer" : "?"; },
        [this](RecordedChange&& f) { changes.push_back(std::move(f)); });
  }
  // Ships the writer's new deltas to the observer.
  std::size_t shipped = 0;
  void ship() {
    for (; shipped < writer.outbox.size(); ++shipped) {
      now += 1000;
      observer.merge(*graph::decode(writer.outbox[shipped]));
    }
  }
};

TEST(RecordingTest, FramesReplayToTheObserversStateAfterEveryFrame) {
  Rig s;
  const auto robot = s.writer.add("robot", "robot");
  s.ship();  // before recording: arrives in the first change as state
  s.start();
  ASSERT_EQ(s.changes.size(), 1u);
  EXPECT_EQ(s.changes[0].delta.kind, graph::GraphDelta::Kind::kState);
  std::vector<Digest128> digests;
  for (int i = 0; i < 5; ++i) {
    auto tx = s.writer.g.begin();
    ASSERT_TRUE(tx.set(robot, "battery", 0.1 * i).ok());
    ASSERT_TRUE(tx.commit().ok());
    s.ship();
    digests.push_back(s.observer.digest());
  }
  ASSERT_EQ(s.changes.size(), 6u);
  EXPECT_EQ(s.changes[3].origin, "writer");

  History h;
  for (const RecordedChange& f : s.changes) h.add(f);
  for (std::uint64_t i = 1; i < h.end(); ++i) {
    graph::ChangeBatch changes;
    auto g = h.state_after(i, &changes);
    ASSERT_TRUE(g.ok()) << g.error().to_string();
    EXPECT_EQ((*g)->node_count(), 1u);
    EXPECT_EQ(*(*g)->get<double>(robot, "battery"), 0.1 * static_cast<double>(i - 1));
    ASSERT_EQ(changes.nodes.size(), 1u) << "frame " << i;
    EXPECT_EQ(changes.origin_name, "writer");
  }
}

TEST(RecordingTest, AFileReadsBackFrameForFrame) {
  Rig s;
  s.start();
  const auto a = s.writer.add("room", "kitchen");
  const auto b = s.writer.add("robot", "robot");
  {
    auto tx = s.writer.g.begin();
    ASSERT_TRUE(tx.insert_edge(b, a, "in").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  s.ship();
  const std::string path = temp_path("a.qrec");
  auto w = RecordWriter::create(path, {.max_bytes = 1 << 20, .start_wall_ns = 42});
  ASSERT_TRUE(w.ok()) << w.error().to_string();
  for (const RecordedChange& f : s.changes) ASSERT_TRUE((*w)->append(f, {}).ok());
  ASSERT_TRUE((*w)->flush().ok());
  auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().to_string();
  EXPECT_EQ(rec->start_wall_ns, 42u);
  EXPECT_TRUE(rec->note.empty());
  ASSERT_EQ(rec->changes.size(), s.changes.size());
  graph::Graph replay(replay_replica_id());
  for (std::size_t i = 0; i < rec->changes.size(); ++i) {
    EXPECT_EQ(rec->changes[i].t_ns, s.changes[i].t_ns);
    EXPECT_EQ(rec->changes[i].origin, s.changes[i].origin);
    replay.merge(rec->changes[i].delta);
  }
  EXPECT_EQ(replay.digest(), s.observer.digest());
}

TEST(RecordingTest, AFileStaysWithinItsBoundAndTheNewestPartReplaysOnItsOwn) {
  Rig s;
  const auto robot = s.writer.add("robot", "robot");
  s.ship();
  const std::string path = temp_path("bounded.qrec");
  const std::uint64_t max_bytes = 8 << 10;
  auto w = RecordWriter::create(path, {.max_bytes = max_bytes});
  ASSERT_TRUE(w.ok());
  s.recorder = std::make_unique<GraphRecorder>(
      s.observer, [&] { return s.now; },
      [](const graph::ReplicaId&) { return std::string("writer"); },
      [&](RecordedChange&& f) { ASSERT_TRUE((*w)->append(f, [&] { return s.observer.state(); }).ok()); });
  for (int i = 0; i < 400; ++i) {
    auto tx = s.writer.g.begin();
    ASSERT_TRUE(tx.set(robot, "note", std::string(40, static_cast<char>('a' + i % 26))).ok());
    ASSERT_TRUE(tx.commit().ok());
    s.ship();
  }
  ASSERT_TRUE((*w)->flush().ok());
  EXPECT_GE((*w)->rotations(), 2u);
  EXPECT_LE(fs::file_size(path) + fs::file_size(path + ".1"), max_bytes);
  // The current file starts with a state: replayed alone, it is the observer's state. (A
  // rotation's snapshot is taken before the change that triggered it, which follows it.)
  auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().to_string();
  EXPECT_EQ(rec->changes.front().delta.kind, graph::GraphDelta::Kind::kState);
  graph::Graph replay(replay_replica_id());
  for (const RecordedChange& f : rec->changes) replay.merge(f.delta);
  EXPECT_EQ(replay.digest(), s.observer.digest());
}

TEST(RecordingTest, DamageIsReportedWithTheFrameAndItsOffsetAndACutTailIsLeftOut) {
  Rig s;
  s.start();
  s.writer.add("room", "kitchen");
  s.writer.add("room", "hall");
  s.ship();
  std::vector<std::uint8_t> bytes;
  encode_header(0, bytes);
  for (const RecordedChange& f : s.changes) encode_change(f, bytes);
  ASSERT_EQ(s.changes.size(), 2u);

  auto whole = parse_recording(bytes, "run.qrec");
  ASSERT_TRUE(whole.ok());
  EXPECT_EQ(whole->changes.size(), 2u);

  auto cut = bytes;
  cut.resize(cut.size() - 5);
  auto r = parse_recording(cut, "run.qrec");
  ASSERT_TRUE(r.ok()) << r.error().to_string();
  EXPECT_EQ(r->changes.size(), 1u);
  EXPECT_NE(r->note.find("frame 1"), std::string::npos) << r->note;

  auto flipped = bytes;
  flipped[bytes.size() - 12] ^= 0x40;  // inside change 1's delta
  auto f = parse_recording(flipped, "run.qrec");
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().message.find("run.qrec: frame 1 at byte"), std::string::npos)
      << f.error().message;
  EXPECT_NE(f.error().message.find("hash"), std::string::npos) << f.error().message;

  std::vector<std::uint8_t> json = {'{', '"', 'n', 'o', 'd', 'e', 's',
                                    '"', ':', '[', ']', '}', ' ', ' '};
  auto j = parse_recording(json, "world.json");
  ASSERT_FALSE(j.ok());
  EXPECT_NE(j.error().message.find("world.json: not a Quiver recording"), std::string::npos)
      << j.error().message;

  auto v = bytes;
  v[4] = 9;
  auto vr = parse_recording(v, "run.qrec");
  ASSERT_FALSE(vr.ok());
  EXPECT_EQ(vr.error().code, ErrorCode::kUnsupportedVersion);

  auto missing = read_recording(temp_path("no-such.qrec"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("no-such.qrec"), std::string::npos);
}

TEST(RecordingTest, AHistoryOverItsBoundFoldsOldFramesAndStillRebuildsEveryListedOne) {
  Rig s;
  s.start();
  const auto robot = s.writer.add("robot", "robot");
  for (int i = 0; i < 200; ++i) {
    auto tx = s.writer.g.begin();
    ASSERT_TRUE(tx.set(robot, "count", i).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  s.ship();
  History h(4 << 10);
  for (const RecordedChange& f : s.changes) h.add(f);
  EXPECT_GT(h.folded(), 0u);
  EXPECT_LE(h.bytes(), 4u << 10);
  EXPECT_EQ(h.end(), s.changes.size());
  for (std::uint64_t i : {h.begin(), (h.begin() + h.end()) / 2, h.end() - 1}) {
    auto g = h.state_after(i);
    ASSERT_TRUE(g.ok());
    EXPECT_EQ(*(*g)->get<std::int64_t>(robot, "count"), static_cast<std::int64_t>(i) - 1)
        << "frame " << i;
  }
  EXPECT_FALSE(h.state_after(0).ok());
  EXPECT_FALSE(h.change(h.end()).ok());
}

}  // namespace
}  // namespace quiver::agents::recording
