// The viewer's parts without a browser: the event hub never blocks its publisher and tells a
// lagging page to reload; the JSON a page gets names writers, conflicts, poses and shapes; the
// timeline lists what each change did and rebuilds the state after it.

#include <gtest/gtest.h>

#include <thread>

#include "graph_test_util.h"
#include "quiver/agents/view/recording/graph_recorder.h"
#include "quiver/agents/view/viewer/event_hub.h"
#include "quiver/agents/view/viewer/change_timeline.h"
#include "quiver/agents/view/viewer/view_json.h"
#include "quiver/agents/view/viewer/viewer.h"

namespace quiver::agents::viewer {
namespace {

using graph::testing::Peer;

TEST(EventHubTest, AReaderGetsMessagesInOrderAndALaggingOneIsToldToResync) {
  EventHub hub(4);
  std::uint64_t cursor = hub.next();
  hub.publish("change", "{\"n\":1}");
  hub.publish("change", "{\"n\":2}");
  EXPECT_EQ(hub.wait(cursor, 0), "id: 0\nevent: change\ndata: {\"n\":1}\n\n");
  EXPECT_EQ(hub.wait(cursor, 0), "id: 1\nevent: change\ndata: {\"n\":2}\n\n");
  EXPECT_EQ(hub.wait(cursor, 10), "");  // nothing new: a timeout, not a block
  for (int i = 0; i < 10; ++i) hub.publish("change", "{}");  // the ring holds 4: cursor 2 is gone
  EXPECT_EQ(hub.wait(cursor, 0), "event: resync\ndata: {}\n\n");
  EXPECT_EQ(cursor, hub.next());
  std::thread closer([&] { hub.close(); });
  EXPECT_EQ(hub.wait(cursor, 5000), "");
  closer.join();
  EXPECT_TRUE(hub.closed());
}

TEST(ViewJsonTest, NodesCarryTypedValuesTheirWritersConflictsPosesAndShapes) {
  Peer a(1), b(2);
  const auto world = a.add("world", "world");
  const auto robot = a.add("robot", "robot");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(world, robot, graph::Pose{{1, 2, 3}, {1, 0, 0, 0}}, 7).ok());
    ASSERT_TRUE(tx.set(robot, "shape", "sphere").ok());
    ASSERT_TRUE(tx.set(robot, "shape_radius", 0.25).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  for (Peer* p : {&a, &b}) {  // concurrent writes: a conflict
    auto tx = p->g.begin();
    ASSERT_TRUE(tx.set(robot, "battery", p == &a ? 0.5 : 0.7).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  a.receive_all(b);
  Decor d;
  d.name_of = [](const graph::ReplicaId& r) { return r.agent == 1 ? std::string("alice") : std::string("bob"); };
  d.locks[robot] = {"alice", 3, 5};
  const auto j = node_json(a.g, robot, d);
  EXPECT_EQ(j["name"], "robot");
  EXPECT_EQ(j["pose"]["t"], nlohmann::json({1.0, 2.0, 3.0}));
  EXPECT_EQ(j["pose"]["parent"], node_key(world));
  EXPECT_EQ(j["shape"]["kind"], "sphere");
  EXPECT_EQ(j["lock"]["holder"], "alice");
  bool battery = false;
  for (const auto& attr : j["attrs"])
    if (attr["name"] == "battery") {
      battery = true;
      EXPECT_EQ(attr["type"], "double");
      ASSERT_EQ(attr["values"].size(), 2u) << attr.dump();
      std::set<std::string> writers{attr["values"][0]["writer"], attr["values"][1]["writer"]};
      EXPECT_EQ(writers, (std::set<std::string>{"alice", "bob"}));
    }
  EXPECT_TRUE(battery);
  // The world is in the RT tree and in no symbolic edge: geometric; the same rule as the pictures.
  EXPECT_TRUE(node_json(a.g, world, d)["geometric"].get<bool>());
}

TEST(ViewJsonTest, TheAccumulatorSendsPosesApartAndWhatWentAsDeleted) {
  Peer a(1);
  const auto world = a.add("world", "world");
  const auto arm = a.add("arm", "arm");
  const auto cup = a.add("cup", "cup");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(world, arm, graph::Pose{}, 1).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ChangeAccumulator acc;
  const auto sub = a.g.subscribe([&](const graph::ChangeBatch& b) { acc.add(b); });
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(world, arm, graph::Pose{{0.5, 0, 0}, {1, 0, 0, 0}}, 2).ok());
    ASSERT_TRUE(tx.delete_node(cup).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  const auto m = acc.drain(a.g, Decor{});
  EXPECT_TRUE(acc.empty());
  ASSERT_EQ(m["poses"].size(), 1u) << m.dump();
  EXPECT_EQ(m["poses"][0]["t"][0], 0.5);
  EXPECT_EQ(m["nodes"].size(), 0u) << "a pose sample alone does not resend the node";
  EXPECT_EQ(m["deleted_nodes"], nlohmann::json::array({node_key(cup)}));
  a.g.unsubscribe(sub);
}

TEST(TimelineTest, ListsWhatEachFrameDidAndRebuildsTheStateAfterIt) {
  Peer writer(7);
  graph::Graph observer(graph::ReplicaId{9, 1});
  Timeline t;
  std::int64_t now = 0;
  recording::GraphRecorder rec(
      observer, [&] { return now += 1'000'000; }, [](const graph::ReplicaId&) { return std::string("writer"); },
      [&](recording::RecordedChange&& f) { t.add_change(std::move(f)); });
  const auto kitchen = writer.add("room", "kitchen");
  const auto cup = writer.add("cup", "cup");
  {
    auto tx = writer.g.begin();
    ASSERT_TRUE(tx.insert_edge(cup, kitchen, "in").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  for (const auto& m : writer.outbox) observer.merge(*graph::decode(m));
  ASSERT_EQ(t.end(), 3u);
  const auto list = t.list(0, 10);
  ASSERT_EQ(list["frames"].size(), 3u);
  EXPECT_EQ(list["frames"][1]["summary"]["created"], nlohmann::json::array({"cup (cup)"}));
  EXPECT_EQ(list["frames"][2]["summary"]["edges_created"], nlohmann::json::array({"cup -[in]-> kitchen"}));
  EXPECT_EQ(list["frames"][2]["origin"], "writer");
  EXPECT_EQ(list["frames"][2]["t_ms"], 3.0);
  auto s = t.state_after(1, Decor{});
  ASSERT_TRUE(s.ok());
  EXPECT_EQ((*s)["nodes"].size(), 2u);
  EXPECT_EQ((*s)["edges"].size(), 0u);
  EXPECT_EQ((*s)["changed"], nlohmann::json::array({node_key(cup)}));
  EXPECT_FALSE(t.state_after(3, Decor{}).ok());
}

// A viewer destroyed as soon as start() returned (`quiver view --replay` of a damaged file) must
// stop its server: before the fix, httplib's stop() could come before its listen loop began, and
// the destructor then waited for ever (the ctest timeout catches a hang).
TEST(ViewerTest, AViewerDestroyedRightAfterStartStopsItsServer) {
  graph::Graph g(graph::ReplicaId{5, 1});
  ViewerOptions o;
  o.port = 0;
  for (int i = 0; i < 200; ++i) {
    auto v = Viewer::start(g, o, Hooks{});
    ASSERT_TRUE(v.ok()) << v.error().to_string();
    EXPECT_GT((*v)->port(), 0);
  }
}

}  // namespace
}  // namespace quiver::agents::viewer
