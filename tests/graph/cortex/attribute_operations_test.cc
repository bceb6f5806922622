// Translation onto Quiver of RoboComp CORTEX's DSR tests, file tests/graph/attribute_operations.cpp
// (robocomp/cortex). Each TEST names the CORTEX TEST_CASE / SECTION it keeps the intent of.
//
// CORTEX runs every case twice (SyncMode::CRDT and SyncMode::LWW); Quiver has one merge semantics
// (a causal CRDT), so each case runs once. CORTEX's graph is seeded from make_edge_config_file()
// (tests/utils.h): data/edge_world.json holds the same nodes, attributes and RT edges in Quiver's
// world format; DSR node 100 is "root", 150 is "room", 200 is "Shadow". DSR's `int` attributes are
// int32 (Value::int32 here); DSR's update_node / insert_or_assign_edge are a committed transaction.

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {
namespace {

using graph::ValueType;

// The CORTEX fixture: a graph loaded from the edge config file.
class CortexAttributes : public CortexWorldTest {
 protected:
  CortexAttributes() : CortexWorldTest("edge_world.json", ReplicaId{0xC0, 1}) {}
  void SetUp() override {
    CortexWorldTest::SetUp();
    rt_root_room = EdgeKey{root, room, graph::symbols::rt()};
  }

  // DSR's remove_attrib_local + update_node; returns what remove_attrib_local returned.
  bool remove_and_commit(NodeId id, std::string_view attr) {
    auto had = remove_attr_and_commit(id, attr);
    EXPECT_TRUE(had.ok()) << had.error().to_string();
    return had.ok() && *had;
  }

  EdgeKey rt_root_room;
};

using CortexAttributeOperations = CortexAttributes;

// ---- TEST_CASE "Attributes operations (Compile time type-checked)" ----

// CORTEX attribute_operations.cpp, "Attributes operations (Compile time type-checked)" /
// "Insert attribute (node) and insert node in G". (a)
TEST_F(CortexAttributeOperations, InsertAttributeNodeAndInsertNodeInG) {
  ASSERT_EQ(g.attr(root, "int_"), nullptr);
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(918273)).ok());
  const Value* v = g.attr(root, "int_");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->type(), ValueType::kInt32);
}

// CORTEX attribute_operations.cpp, "Attributes operations (Compile time type-checked)" /
// "Insert an string attribute and update G". (a)
TEST_F(CortexAttributeOperations, InsertAnStringAttributeAndUpdateG) {
  ASSERT_TRUE(set_and_commit(root, "string_", Value(std::string("string att"))).ok());
  ASSERT_NE(g.attr(root, "string_"), nullptr);
  // Updating the node again with the same content succeeds (DSR's second update_node returns true).
  EXPECT_TRUE(set_and_commit(root, "string_", Value(std::string("string att"))).ok());
  EXPECT_EQ(g.get<std::string>(root, "string_").value(), "string att");
}

// CORTEX attribute_operations.cpp, "Attributes operations (Compile time type-checked)" /
// "Insert attribute (edge) and insert in G". (a)
TEST_F(CortexAttributeOperations, InsertAttributeEdgeAndInsertInG) {
  ASSERT_TRUE(g.has_edge(root, room, "RT"));
  ASSERT_TRUE(set_edge_and_commit(rt_root_room, "int_", Value::int32(123)).ok());
  ASSERT_NE(g.edge_attr(rt_root_room, "int_"), nullptr);
  EXPECT_EQ(g.get<std::int32_t>(rt_root_room, "int_").value(), 123);
  // insert_or_assign_edge of the same edge again succeeds and keeps the attribute.
  auto tx = g.begin();
  ASSERT_TRUE(tx.insert_edge(root, room, "RT", {{Symbol("int_"), Value::int32(123)}}).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(g.get<std::int32_t>(rt_root_room, "int_").value(), 123);
  // The edge is still root -> room with the pose the file gave it (DSR's edge keeps its
  // rt_translation / rt_rotation_euler_xyz).
  auto rt = g.rt_edge(room);
  ASSERT_TRUE(rt.has_value());
  EXPECT_EQ(rt->parent, root);
  EXPECT_EQ(rt->pose, graph::Pose::identity());
}

// CORTEX attribute_operations.cpp, "Attributes operations (Compile time type-checked)" /
// "Insert rt_covariance attribute on RT edge". (a)
TEST_F(CortexAttributeOperations, InsertRtCovarianceAttributeOnRTEdge) {
  const graph::FloatVec covariance(36, 0.5f);
  ASSERT_TRUE(set_edge_and_commit(rt_root_room, "rt_covariance", Value(covariance)).ok());
  ASSERT_TRUE(g.has_edge(root, room, "RT"));
  auto stored = g.get<graph::FloatVec>(rt_root_room, "rt_covariance");
  ASSERT_TRUE(stored.ok()) << stored.error().to_string();
  EXPECT_EQ(*stored, covariance);
}

// CORTEX attribute_operations.cpp, "Attributes operations (Compile time type-checked)" /
// "Update attribute and update G". (a)
TEST_F(CortexAttributeOperations, UpdateAttributeAndUpdateG) {
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(7)).ok());
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(125)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "int_").value(), 125);
  EXPECT_TRUE(set_and_commit(root, "int_", Value::int32(125)).ok());
}

// CORTEX attribute_operations.cpp, "Attributes operations (Compile time type-checked)" /
// "Get attribute by name". (a)
TEST_F(CortexAttributeOperations, GetAttributeByName) {
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(125)).ok());
  auto att = g.get<std::int32_t>(root, "int_");
  ASSERT_TRUE(att.ok()) << att.error().to_string();
  EXPECT_EQ(*att, 125);
}

// ---- TEST_CASE "Attributes operations II (Runtime time type-checked)" ----

// CORTEX attribute_operations.cpp, "Attributes operations II (Runtime time type-checked)" /
// "Insert an attribute". (a) DSR throws when a float is written over the int32 attribute; Quiver
// refuses the write with kTypeMismatch.
TEST_F(CortexAttributeOperations, RuntimeInsertAnAttribute) {
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(133)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "int_").value(), 133);
  auto tx = g.begin();
  Status s = tx.set(root, "int_", Value(133.0f));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTypeMismatch);
  EXPECT_EQ(g.get<std::int32_t>(root, "int_").value(), 133);
}

// CORTEX attribute_operations.cpp, "Attributes operations II (Runtime time type-checked)" /
// "Modify an attribute". (a)
TEST_F(CortexAttributeOperations, RuntimeModifyAnAttribute) {
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(root, "int_", Value::int32(133)).ok());
  ASSERT_TRUE(tx.set(root, "int_", Value::int32(111)).ok());  // modified before the update
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "int_").value(), 111);
}

// CORTEX attribute_operations.cpp, "Attributes operations II (Runtime time type-checked)" /
// "Update attribute". (a)
TEST_F(CortexAttributeOperations, RuntimeUpdateAttribute) {
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(133)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "int_").value(), 133);
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(177)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "int_").value(), 177);
  EXPECT_EQ(*g.attr(root, "int_"), Value::int32(177));
}

// CORTEX attribute_operations.cpp, "Attributes operations II (Runtime time type-checked)" /
// "Remove an attribute". (a)
TEST_F(CortexAttributeOperations, RuntimeRemoveAnAttribute) {
  ASSERT_TRUE(set_and_commit(root, "int_", Value::int32(133)).ok());
  ASSERT_NE(g.attr(root, "int_"), nullptr);
  auto tx = g.begin();
  auto had = tx.remove_attr(root, "int_");
  ASSERT_TRUE(had.ok());
  EXPECT_TRUE(*had);
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(g.attr(root, "int_"), nullptr);
}

// CORTEX attribute_operations.cpp, "Attributes operations II (Runtime time type-checked)" /
// "Insert attribute (edge) and insert in G". (a)
TEST_F(CortexAttributeOperations, RuntimeInsertAttributeEdgeAndInsertInG) {
  ASSERT_EQ(g.edge_attr(rt_root_room, "new_int"), nullptr);  // add_attrib_local: it was absent
  ASSERT_TRUE(set_edge_and_commit(rt_root_room, "new_int", Value::int32(123)).ok());
  ASSERT_NE(g.edge_attr(rt_root_room, "new_int"), nullptr);
  EXPECT_EQ(g.get<std::int32_t>(rt_root_room, "new_int").value(), 123);
  auto tx = g.begin();
  EXPECT_TRUE(tx.insert_edge(root, room, "RT", {{Symbol("new_int"), Value::int32(123)}}).ok());
  EXPECT_TRUE(tx.commit().ok());
}

// CORTEX attribute_operations.cpp, "Attributes operations II (Runtime time type-checked)" /
// "Runtime insert rt_covariance attribute on RT edge". (a)
TEST_F(CortexAttributeOperations, RuntimeInsertRtCovarianceAttributeOnRTEdge) {
  const graph::FloatVec covariance(36, 1.25f);
  auto tx = g.begin();
  ASSERT_TRUE(tx.set_edge_attr(rt_root_room, Symbol("rt_covariance"), Value(covariance)).ok());
  ASSERT_TRUE(tx.commit().ok());
  auto stored = g.get<graph::FloatVec>(rt_root_room, "rt_covariance");
  ASSERT_TRUE(stored.ok()) << stored.error().to_string();
  EXPECT_EQ(*stored, covariance);
}

// ---- TEST_CASE "Other attribute operations and checks" ----

// CORTEX attribute_operations.cpp, "Other attribute operations and checks" /
// "Get attribute timestamp". (b) Quiver attributes carry no wall-clock timestamp
// (docs/dsr-api.md, "Not carried over"): each value carries the dot of the write that made it
// (which replica, which of its writes), ordered as timestamps are. We assert that instead.
TEST_F(CortexAttributeOperations, GetAttributeTimestamp) {
  ASSERT_TRUE(set_and_commit(root, "string_", Value(std::string("string att"))).ok());
  auto first = g.attr_values(root, Symbol("string_"));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_FALSE(first[0].dot.is_null());
  EXPECT_EQ(first[0].dot.replica, g.replica());
  ASSERT_TRUE(set_and_commit(root, "string_", Value(std::string("later"))).ok());
  auto second = g.attr_values(root, Symbol("string_"));
  ASSERT_EQ(second.size(), 1u);
  EXPECT_GT(second[0].dot.counter, first[0].dot.counter);
}

// CORTEX attribute_operations.cpp, "Other attribute operations and checks" /
// "Get attribute by name using only the id (no references)". (a) Quiver reads by id only; the
// by-name and by-Symbol routes give the same value.
TEST_F(CortexAttributeOperations, GetAttributeByNameUsingOnlyTheId) {
  ASSERT_TRUE(set_and_commit(root, "string_", Value(std::string("string att"))).ok());
  const NodeId by_name = g.find_node("root").value();
  auto str1 = g.get<std::string>(root, "string_");
  ASSERT_TRUE(str1.ok());
  const Value* str2 = g.attr(by_name, Symbol("string_"));
  ASSERT_NE(str2, nullptr);
  ASSERT_NE(str2->get_if<std::string>(), nullptr);
  EXPECT_EQ(*str1, *str2->get_if<std::string>());
  EXPECT_EQ(*str1, "string att");
}

// CORTEX attribute_operations.cpp, "Other attribute operations and checks" /
// "In add_or_modify_attrib_local, we can pass a reference or move the value". (a)
TEST_F(CortexAttributeOperations, PassAReferenceOrMoveTheValue) {
  std::string stratt("string att lvalue");
  std::string strattmove("string att rvalue");
  ASSERT_TRUE(set_and_commit(root, "string_", stratt).ok());
  EXPECT_EQ(g.get<std::string>(root, "string_").value(), stratt);
  ASSERT_TRUE(set_and_commit(root, "string_", std::move(strattmove)).ok());
  EXPECT_EQ(g.get<std::string>(root, "string_").value(), "string att rvalue");
}

// CORTEX attribute_operations.cpp, "Other attribute operations and checks" /
// "runtime_checked_add_or_modify_attrib_local is equivalent to add_or_modify_attrib_local". (a)
// Quiver's two forms are set() with an interned Symbol and set() with a string name.
TEST_F(CortexAttributeOperations, RuntimeCheckedAddOrModifyIsEquivalent) {
  const std::string stratt("string att lvalue");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(root, Symbol("string_"), Value(stratt)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.get<std::string>(root, "string_").value(), stratt);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(root, std::string_view("string_"), Value(stratt)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.get<std::string>(root, "string_").value(), stratt);
}

// CORTEX attribute_operations.cpp, "Other attribute operations and checks" /
// "add_attrib_local is equivalent to runtime_checked_add_attrib_local". (a) DSR's add_attrib_local
// is tx.add(); its runtime_checked_ form (the attribute named by a run-time string) is the same
// call with the Symbol made from that string. A second add in the same local copy (transaction)
// is refused (kAlreadyExists), as DSR's returns false.
TEST_F(CortexAttributeOperations, AddAttribLocalIsEquivalentToRuntimeCheckedAdd) {
  const std::string stratt("string att");
  remove_and_commit(root, "string_");
  EXPECT_FALSE(g.get<std::string>(root, "string_").ok());
  {
    auto tx = g.begin();
    EXPECT_TRUE(tx.add(root, Symbol("string_"), Value(stratt)).ok());
    Status again = tx.add(root, Symbol("string_"), Value(stratt));
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value1 = g.get<std::string>(root, "string_");
  ASSERT_TRUE(value1.ok());

  remove_and_commit(root, "string_");
  EXPECT_FALSE(g.get<std::string>(root, "string_").ok());
  {
    const std::string runtime_name{"string_"};
    auto tx = g.begin();
    EXPECT_TRUE(tx.add(root, Symbol(runtime_name), Value(stratt)).ok());
    Status again = tx.add(root, Symbol(runtime_name), Value(stratt));
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value2 = g.get<std::string>(root, "string_");
  ASSERT_TRUE(value2.ok());
  EXPECT_EQ(*value1, *value2);
}

// CORTEX attribute_operations.cpp, "Other attribute operations and checks" /
// "modify_attrib_local is equivalent to runtime_checked_modify_attrib_local". (a) DSR's
// modify_attrib_local is tx.modify(): refused (kNotFound) for an attribute the node lacks, accepted
// once an add earlier in the same local copy (transaction) gave it; the runtime_checked_ form is
// the same call with the Symbol made from a run-time string. DSR reads the local copy before
// update_node(); here that is what the open transaction wrote (written_in()).
TEST_F(CortexAttributeOperations, ModifyAttribLocalIsEquivalentToRuntimeCheckedModify) {
  const std::string stratt("string att");
  const Symbol attr("string_");
  remove_and_commit(root, "string_");
  EXPECT_FALSE(g.get<std::string>(root, "string_").ok());
  {
    auto tx = g.begin();
    Status missing = tx.modify(root, attr, Value(stratt));
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
    EXPECT_TRUE(tx.add(root, attr, Value(std::string("initial_value"))).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value(std::string("initial_value")));
    EXPECT_TRUE(tx.modify(root, attr, Value(stratt)).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value(stratt));
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value1 = g.get<std::string>(root, "string_");
  ASSERT_TRUE(value1.ok());

  remove_and_commit(root, "string_");
  EXPECT_FALSE(g.get<std::string>(root, "string_").ok());
  {
    const std::string runtime_name{"string_"};
    auto tx = g.begin();
    Status missing = tx.modify(root, Symbol(runtime_name), Value(stratt));
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
    EXPECT_TRUE(tx.add(root, attr, Value(std::string("initial_value"))).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value(std::string("initial_value")));
    EXPECT_TRUE(tx.modify(root, Symbol(runtime_name), Value(stratt)).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value(stratt));
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value2 = g.get<std::string>(root, "string_");
  ASSERT_TRUE(value2.ok());
  EXPECT_EQ(*value1, *value2);
}

// ---- TEST_CASE "Native types in attributes" ----
// Each CORTEX section writes one attribute of a native type and checks that the node read back
// holds the same value. Here: the stored value has exactly that type and payload.

template <class T>
void expect_round_trip(Graph& g, NodeId id, const char* attr, Value v, const T& expected,
                       ValueType type) {
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(id, attr, std::move(v)).ok());
  ASSERT_TRUE(tx.commit().ok());
  const Value* stored = g.attr(id, attr);
  ASSERT_NE(stored, nullptr) << attr;
  EXPECT_EQ(stored->type(), type) << attr;
  auto got = g.get<T>(id, attr);
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  EXPECT_EQ(*got, expected) << attr;
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a string attribute". (a)
TEST_F(CortexAttributeOperations, InsertAStringAttribute) {
  expect_round_trip<std::string>(g, root, "string_", Value(std::string("string att")), "string att",
                                 ValueType::kString);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an int32 attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnInt32Attribute) {
  expect_round_trip<std::int32_t>(g, root, "int_", Value::int32(11), 11, ValueType::kInt32);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an uint32 attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnUint32Attribute) {
  expect_round_trip<std::uint32_t>(g, root, "uint_", Value::uint32(11u), 11u, ValueType::kUInt32);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an uint64 attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnUint64Attribute) {
  expect_round_trip<std::uint64_t>(g, root, "uint64_", Value(std::uint64_t{1}), std::uint64_t{1},
                                   ValueType::kUInt64);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a float attribute". (a)
TEST_F(CortexAttributeOperations, InsertAFloatAttribute) {
  expect_round_trip<float>(g, root, "float_", Value(11.0f), 11.0f, ValueType::kFloat);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a float_vector attribute". (a)
TEST_F(CortexAttributeOperations, InsertAFloatVectorAttribute) {
  const graph::FloatVec v{11.0f, 167.23f, 55.66f};
  expect_round_trip<graph::FloatVec>(g, root, "vec_float", Value(v), v, ValueType::kFloatVec);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a bool attribute". (a)
TEST_F(CortexAttributeOperations, InsertABoolAttribute) {
  expect_round_trip<bool>(g, root, "bool_", Value(true), true, ValueType::kBool);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a byte_vector attribute"
// (the first of the two sections with this title: std::vector<uint8_t>). (a)
TEST_F(CortexAttributeOperations, InsertAByteVectorAttribute) {
  const graph::Bytes v{11, 167, 55};
  expect_round_trip<graph::Bytes>(g, root, "vec_byte", Value(v), v, ValueType::kBytes);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a double attribute". (a)
TEST_F(CortexAttributeOperations, InsertADoubleAttribute) {
  expect_round_trip<double>(g, root, "doub", Value(33.3), 33.3, ValueType::kDouble);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert a byte_vector attribute"
// (the second section with this title, which writes std::vector<uint64_t>). (a)
TEST_F(CortexAttributeOperations, InsertAByteVectorAttributeUInt64Vec) {
  const graph::UInt64Vec v{11, 167, 55};
  expect_round_trip<graph::UInt64Vec>(g, root, "vec_u64", Value(v), v, ValueType::kUInt64Vec);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an array<float, 2> attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnArrayFloat2Attribute) {
  const graph::Vec2f v{11.0f, 167.0f};
  expect_round_trip<graph::Vec2f>(g, root, "vec2_", Value(v), v, ValueType::kVec2f);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an array<float, 3> attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnArrayFloat3Attribute) {
  const graph::Vec3f v{11.0f, 167.0f, 0.0f};
  expect_round_trip<graph::Vec3f>(g, root, "vec3_", Value(v), v, ValueType::kVec3f);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an array<float, 4> attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnArrayFloat4Attribute) {
  const graph::Vec4f v{11.0f, 167.0f, 1.0f, 0.0f};
  expect_round_trip<graph::Vec4f>(g, root, "vec4_", Value(v), v, ValueType::kVec4f);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" / "Insert an array<float, 6> attribute". (a)
TEST_F(CortexAttributeOperations, InsertAnArrayFloat6Attribute) {
  const graph::Vec6f v{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 1.0f};
  expect_round_trip<graph::Vec6f>(g, root, "vec6_", Value(v), v, ValueType::kVec6f);
}

// CORTEX attribute_operations.cpp, "Native types in attributes" /
// "Insert an array<float, 6> attribute without reference wrapper". (a) Quiver's typed reads
// always return a copy, so both DSR registrations are the same read here.
TEST_F(CortexAttributeOperations, InsertAnArrayFloat6AttributeWithoutReferenceWrapper) {
  const graph::Vec6f v{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 0.0f};
  expect_round_trip<graph::Vec6f>(g, root, "att_no_reference", Value(v), v, ValueType::kVec6f);
}

}  // namespace
}  // namespace quiver::cortex_tests
