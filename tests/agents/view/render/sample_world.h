#pragma once
// A small world and a small recording of its evolution, built through the public API, for the
// renderer's tests and the CLI test's helper (make_sample_recording).
//
// The world: world -RT-> kitchen, world -RT-> robot, robot -RT-> camera; robot -in-> kitchen,
// mug -on-> table, table -in-> kitchen; a lonely note. Geometric: world and camera.
//
// The recording (changes):
//   0  the initial state (a kState fragment), origin "loader"
//   1  planner: creates person, person -with-> robot
//   2  speech:  sets robot.speaking = true
//   3  person:  moves camera (a pose update: geometry only)
//   4  planner: deletes person

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "quiver/agents/view/recording/recorded_change.h"
#include "quiver/agents/view/recording/record_file.h"
#include "quiver/graph/graph.h"

namespace quiver::render_test {

inline void check(bool ok, const char* what) {
  if (!ok) throw std::runtime_error(std::string("sample world: ") + what);
}

/// Builds the sample world in `g` (one transaction).
inline void build_sample_world(graph::Graph& g) {
  auto tx = g.begin();
  const auto world = *tx.create_node("world", "world");
  const auto kitchen = *tx.create_node("room", "kitchen");
  const auto robot = *tx.create_node("robot", "robot", {{"battery", graph::Value(0.8)}});
  const auto camera = *tx.create_node("camera", "camera");
  const auto mug = *tx.create_node("mug", "mug");
  const auto table = *tx.create_node("table", "table");
  check(tx.create_node("note", "note").ok(), "note");
  check(tx.set_rt(world, kitchen, graph::Pose::identity()).ok(), "rt kitchen");
  check(tx.set_rt(world, robot, graph::Pose::identity()).ok(), "rt robot");
  check(tx.set_rt(robot, camera, graph::Pose::identity()).ok(), "rt camera");
  check(tx.insert_edge(robot, kitchen, "in").ok(), "in");
  check(tx.insert_edge(mug, table, "on").ok(), "on");
  check(tx.insert_edge(table, kitchen, "in").ok(), "table in");
  check(tx.commit().ok(), "commit");
}

/// The sample recording's changes (times 0, 1.5, 3, 4.5, 6 s).
inline std::vector<agents::recording::RecordedChange> sample_frames() {
  using agents::recording::RecordedChange;
  graph::Graph g(graph::ReplicaId{0x5a3, 1});
  std::vector<graph::GraphDelta> deltas;
  g.set_delta_sink([&](const graph::GraphDelta& d) { deltas.push_back(d); });
  build_sample_world(g);
  std::vector<RecordedChange> changes;
  changes.push_back(RecordedChange{0, "loader", g.state()});
  auto commit = [&](std::int64_t t, const char* origin, auto&& change) {
    deltas.clear();
    auto tx = g.begin();
    change(tx);
    check(tx.commit().ok(), origin);
    check(deltas.size() == 1, "one delta per commit");
    changes.push_back(RecordedChange{t, origin, deltas[0]});
  };
  const auto robot = *g.find_node("robot");
  const auto camera = *g.find_node("camera");
  commit(1'500'000'000, "planner", [&](graph::Transaction& tx) {
    const auto person = *tx.create_node("person", "person");
    check(tx.insert_edge(person, robot, "with").ok(), "with");
  });
  commit(3'000'000'000, "speech", [&](graph::Transaction& tx) {
    check(tx.set(robot, "speaking", graph::Value(true)).ok(), "set");
  });
  commit(4'500'000'000, "person", [&](graph::Transaction& tx) {
    graph::Pose p;
    p.translation = {0.1, 0, 1.2};
    check(tx.set_rt(robot, camera, p, 7).ok(), "pose");
  });
  commit(6'000'000'000, "planner", [&](graph::Transaction& tx) {
    check(tx.delete_node(*g.find_node("person")).ok(), "delete");
  });
  return changes;
}

/// The sample recording as .qrec bytes.
inline std::vector<std::uint8_t> sample_recording_bytes() {
  std::vector<std::uint8_t> out;
  agents::recording::encode_header(/*start_wall_ns=*/0, out);
  for (const auto& f : sample_frames()) agents::recording::encode_change(f, out);
  return out;
}

}  // namespace quiver::render_test
