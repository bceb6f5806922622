#pragma once
// Helpers shared by the translations of RoboComp CORTEX tests/synchronization/fake_network_tests.cpp
// (fake_network_delivery_test.cc, fake_network_ordering_test.cc): level() and the symbolic edge type
// kLink; robot() (CORTEX's make_robot) and Recorder come from cortex_graph_fixture.h.
//
// CORTEX's FakeNetwork queues the deltas its sync engines emit and lets a test post, drop,
// partition and reorder them; some cases also call an engine's apply_remote_*() directly.
// Here:
//  - cases about the network (propagation, drops, partitions, a cold start) run replicas with
//    their Replicators on the in-memory test network (tests/common/test_net.h), simulated time;
//  - cases about the order in which deltas reach an engine record every delta a Graph commits
//    (its delta sink) and join them into another Graph in the order the case wants: Graph::merge
//    is the engine's apply_remote_*.
//
// Mapping: CORTEX fixes node ids (1000, 10, 11); Quiver's ids are the dots of the creations, so
// the tests keep the ids the creations return. CORTEX's edges here have type "RT" used as a
// plain registered type with a "weight" attribute and no pose; a Quiver RT edge needs a pose
// (set_rt), so these tests use a symbolic edge type ("link") for the attribute cases, and an RT
// edge where only insertion and deletion matter. An "attr batch" is a transaction that writes
// attributes only. CORTEX runs each case in LWW or CRDT mode; Quiver has one (CRDT) mode, so a
// CRDT case and its LWW twin run the same scenario.

#include <cstdint>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {

// The symbolic edge type of the attribute cases (CORTEX's plain "RT" edges with a "weight").
inline constexpr const char* kLink = "link";

inline std::int32_t level(const Graph& g, NodeId id) { return g.get<std::int32_t>(id, "level").value_or(-1); }

}  // namespace quiver::cortex_tests
