// Translation of RoboComp CORTEX tests/src/test_dsr_api.cpp onto Quiver, its attribute sections:
// TEST_CASE "Attributes operations (Compile time type-check)", "Attributes operations II (Runtime
// time type-check)", "Other attribute operations and checks" and "Native types in attributes".
// The fixture (CortexDsrApi, the graph every test builds) is in dsr_api_fixture.h;
// docs/dsr-api.md maps each DSR call.

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>

#include "dsr_api_fixture.h"

namespace quiver::cortex_tests {
namespace {

using graph::Bytes;
using graph::FloatVec;
using graph::UInt64Vec;
using graph::Vec2f;
using graph::Vec3f;
using graph::Vec4f;
using graph::Vec6f;

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Attributes operations (Compile time type-check)"

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Insert attribute
// (node) and insert node in G". Class (a).
TEST_F(CortexDsrApi, AttributesInsertAttributeNodeAndInsertNodeInG) {
  EXPECT_TRUE(set(root, "test_int", Value::int32(123)).ok());
  EXPECT_NE(g.attr(root, "test_int"), nullptr);
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Insert an string
// attribute and update G". Class (a).
TEST_F(CortexDsrApi, AttributesInsertAnStringAttributeAndUpdateG) {
  EXPECT_TRUE(set(root, "test_string", Value("string att")).ok());
  EXPECT_NE(g.attr(root, "test_string"), nullptr);
  EXPECT_TRUE(set(root, "test_string", Value("string att")).ok());  // updating again succeeds
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Insert attribute
// (edge) and insert in G". Class (a): an attribute on the RT edge root -> child.
TEST_F(CortexDsrApi, AttributesInsertAttributeEdgeAndInsertInG) {
  ASSERT_TRUE(g.has_edge(root, child, "RT"));
  auto tx = g.begin();
  EXPECT_TRUE(tx.set_edge_attr(rt_key(), "test_int", Value::int32(123)).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_NE(g.edge_attr(rt_key(), "test_int"), nullptr);
  EXPECT_EQ(g.get<std::int32_t>(rt_key(), "test_int").value_or(-1), 123);
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Update attribute
// and update G". Class (a).
TEST_F(CortexDsrApi, AttributesUpdateAttributeAndUpdateG) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(123)).ok());
  EXPECT_TRUE(set(root, "test_int", Value::int32(125)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 125);
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Get attribute by
// name". Class (a).
TEST_F(CortexDsrApi, AttributesGetAttributeByName) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(125)).ok());
  auto att = g.get<std::int32_t>(root, "test_int");
  ASSERT_TRUE(att.ok());
  EXPECT_EQ(*att, 125);
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Attributes operations II (Runtime time type-check)"

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Insert an
// attribute". Class (a): an int32 is written; a float over it is refused (DSR throws; Quiver
// returns kTypeMismatch) and the value stays.
TEST_F(CortexDsrApi, AttributesRuntimeInsertAnAttribute) {
  EXPECT_TRUE(set(root, "test_int", Value::int32(133)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 133);
  Status s = set(root, "test_int", Value(133.0f));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTypeMismatch);
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 133);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Modify an
// attribute". Class (a).
TEST_F(CortexDsrApi, AttributesRuntimeModifyAnAttribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(133)).ok());
  EXPECT_TRUE(set(root, "test_int", Value::int32(111)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 111);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Update
// attribute". Class (a): the value written is the value read, by name and by typed getter.
TEST_F(CortexDsrApi, AttributesRuntimeUpdateAttribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(111)).ok());
  EXPECT_TRUE(set(root, "test_int", Value::int32(177)).ok());
  const Value* v = g.attr(root, "test_int");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(*v, Value::int32(177));
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 177);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Remove an
// attribute". Class (a).
TEST_F(CortexDsrApi, AttributesRuntimeRemoveAnAttribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(177)).ok());
  auto r = remove(root, "test_int");
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(*r);
  EXPECT_EQ(g.attr(root, "test_int"), nullptr);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Insert
// attribute (edge) and insert in G". Class (a).
TEST_F(CortexDsrApi, AttributesRuntimeInsertAttributeEdgeAndInsertInG) {
  auto tx = g.begin();
  EXPECT_TRUE(tx.set_edge_attr(rt_key(), "new_int", Value::int32(123)).ok());
  ASSERT_TRUE(tx.commit().ok());
  auto names = g.edge_attr_names(rt_key());
  EXPECT_NE(std::find(names.begin(), names.end(), Symbol("new_int")), names.end());
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Other attribute operations and checks"

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "Get attribute timestamp".
// Class (b): attributes carry no wall-clock timestamp (docs/dsr-api.md, "Not carried over"); what
// each value carries is the dot of the write that made it: this replica's, within the counters
// the commit published.
TEST_F(CortexDsrApi, OtherGetAttributeTimestamp) {
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(root, "test_string", Value("string att")).ok());
  auto info = tx.commit();
  ASSERT_TRUE(info.ok());
  auto values = g.attr_values(root, Symbol("test_string"));
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values[0].dot.replica, g.replica());
  EXPECT_GE(values[0].dot.counter, info->first_counter);
  EXPECT_LE(values[0].dot.counter, info->last_counter);
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "Get attribute by name using
// only the id (no references)". Class (a): read by id (Quiver always reads by id).
TEST_F(CortexDsrApi, OtherGetAttributeByNameUsingOnlyTheIdNoReferences) {
  ASSERT_TRUE(set(root, "test_string", Value("string att")).ok());
  auto by_id = g.get<std::string>(root, "test_string");
  auto by_name = g.get<std::string>(*g.find_node("root"), "test_string");
  ASSERT_TRUE(by_id.ok());
  ASSERT_TRUE(by_name.ok());
  EXPECT_EQ(*by_id, *by_name);
  EXPECT_EQ(*by_id, "string att");
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "In add_or_modify_attrib_local,
// we can pass a reference or move the value". Class (a).
TEST_F(CortexDsrApi, OtherInAddOrModifyAttribLocalWeCanPassAReferenceOrMoveTheValue) {
  std::string stratt("string att lvalue");
  std::string strattmove("string att rvalue");
  ASSERT_TRUE(set(root, "test_string", stratt).ok());
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), stratt);
  ASSERT_TRUE(set(root, "test_string", std::move(strattmove)).ok());
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), "string att rvalue");
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" /
// "runtime_checked_add_or_modify_attrib_local is equivalent to add_or_modify_attrib_local".
// Class (a): DSR's add_or_modify_attrib_local is tx.set() with the attribute's interned Symbol
// (DSR's compile-time name); its runtime_checked_ form is tx.set() with the name as a run-time
// string. Both write (and type-check) alike.
TEST_F(CortexDsrApi, OtherRuntimeCheckedAddOrModifyAttribLocalIsEquivalentToAddOrModifyAttribLocal) {
  const std::string stratt("string att lvalue");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(root, Symbol("test_string"), Value(stratt)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), stratt);
  {
    const std::string runtime_name{"test_string"};
    auto tx = g.begin();
    EXPECT_TRUE(tx.set(root, std::string_view(runtime_name), Value(stratt)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), stratt);
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "add_attrib_local is
// equivalent to runtime_checked_add_attrib_local". Class (a): DSR's add_attrib_local is tx.add();
// its runtime_checked_ form is the same call with the Symbol made from a run-time string. A
// second add in the same local copy (transaction) is refused (kAlreadyExists), as DSR's returns
// false.
TEST_F(CortexDsrApi, OtherAddAttribLocalIsEquivalentToRuntimeCheckedAddAttribLocal) {
  const std::string stratt("string att");
  ASSERT_TRUE(remove(root, "test_string").ok());
  EXPECT_FALSE(g.get<std::string>(root, "test_string").ok());
  {
    auto tx = g.begin();
    EXPECT_TRUE(tx.add(root, Symbol("test_string"), Value(stratt)).ok());
    Status again = tx.add(root, Symbol("test_string"), Value(stratt));
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value1 = g.get<std::string>(root, "test_string");
  ASSERT_TRUE(value1.ok());

  ASSERT_TRUE(remove(root, "test_string").ok());
  EXPECT_FALSE(g.get<std::string>(root, "test_string").ok());
  {
    const std::string runtime_name{"test_string"};
    auto tx = g.begin();
    EXPECT_TRUE(tx.add(root, Symbol(runtime_name), Value(stratt)).ok());
    Status again = tx.add(root, Symbol(runtime_name), Value(stratt));
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value2 = g.get<std::string>(root, "test_string");
  ASSERT_TRUE(value2.ok());
  EXPECT_EQ(*value1, *value2);
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "modify_attrib_local is
// equivalent to runtime_checked_modify_attrib_local". Class (a): DSR's modify_attrib_local is
// tx.modify(): refused (kNotFound) for an attribute the node lacks, accepted once an add earlier in
// the same local copy (transaction) gave it; the runtime_checked_ form is the same call with the
// Symbol made from a run-time string. DSR reads the local copy before update_node(); here that
// is what the open transaction wrote (written_in()).
TEST_F(CortexDsrApi, OtherModifyAttribLocalIsEquivalentToRuntimeCheckedModifyAttribLocal) {
  const std::string stratt("string att");
  const Symbol attr("test_string");
  const std::string runtime_name{"test_string"};
  std::optional<std::string> values[2];
  for (bool runtime_checked : {false, true}) {
    SCOPED_TRACE(runtime_checked ? "runtime_checked_modify_attrib_local" : "modify_attrib_local");
    const Symbol modified = runtime_checked ? Symbol(runtime_name) : attr;
    ASSERT_TRUE(remove(root, "test_string").ok());
    EXPECT_FALSE(g.get<std::string>(root, "test_string").ok());
    auto tx = g.begin();
    Status missing = tx.modify(root, modified, Value(stratt));
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
    EXPECT_TRUE(tx.add(root, attr, Value("initial_value")).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value("initial_value"));
    EXPECT_TRUE(tx.modify(root, modified, Value(stratt)).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value(stratt));
    ASSERT_TRUE(tx.commit().ok());
    auto value = g.get<std::string>(root, "test_string");
    ASSERT_TRUE(value.ok());
    values[runtime_checked] = *value;
  }
  EXPECT_EQ(values[0], values[1]);
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Native types in attributes". Each "Insert" section writes an attribute of one type
// to node 1 and compares it read from two fetches of the node; each "Get" section reads it with
// the typed getter. Class (a) for all.

template <class T>
void insert_native(CortexDsrApi& t, const char* name, const T& v) {
  ASSERT_TRUE(t.set(t.root, name, Value(v)).ok());
  ASSERT_NE(t.g.attr(t.root, name), nullptr);
  auto first = t.g.get<T>(t.root, name);
  auto second = t.g.get<T>(*t.g.find_node("root"), name);
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(*first, *second);
  EXPECT_EQ(*first, v);
}
template <class T>
void get_native(CortexDsrApi& t, const char* name, const T& v) {
  ASSERT_TRUE(t.set(t.root, name, Value(v)).ok());
  auto st = t.g.get<T>(t.root, name);
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  EXPECT_EQ(*st, v);
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a string attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAStringAttribute) { insert_native<std::string>(*this, "test_string", "string att"); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a string attribute".
TEST_F(CortexDsrApi, NativeTypesGetAStringAttribute) { get_native<std::string>(*this, "test_string", "string att"); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an int32 attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnInt32Attribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(11)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 11);
  EXPECT_EQ(g.attr(root, "test_int")->type(), graph::ValueType::kInt32);
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get an int32 attribute".
TEST_F(CortexDsrApi, NativeTypesGetAnInt32Attribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(11)).ok());
  EXPECT_TRUE(g.get<std::int32_t>(root, "test_int").ok());
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an uint32 attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnUint32Attribute) {
  ASSERT_TRUE(set(root, "test_uint", Value::uint32(11u)).ok());
  EXPECT_EQ(g.get<std::uint32_t>(root, "test_uint").value_or(0), 11u);
  EXPECT_EQ(g.attr(root, "test_uint")->type(), graph::ValueType::kUInt32);
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get an uint32 attribute".
TEST_F(CortexDsrApi, NativeTypesGetAnUint32Attribute) {
  ASSERT_TRUE(set(root, "test_uint", Value::uint32(11u)).ok());
  EXPECT_TRUE(g.get<std::uint32_t>(root, "test_uint").ok());
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an uint64 attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnUint64Attribute) { insert_native<std::uint64_t>(*this, "test_uint64", 1u); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get an uint64 attribute".
TEST_F(CortexDsrApi, NativeTypesGetAnUint64Attribute) { get_native<std::uint64_t>(*this, "test_uint64", 1u); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a float attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAFloatAttribute) { insert_native<float>(*this, "test_float", 11.0f); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a float attribute".
TEST_F(CortexDsrApi, NativeTypesGetAFloatAttribute) { get_native<float>(*this, "test_float", 11.0f); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a float_vector attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAFloatVectorAttribute) {
  insert_native<FloatVec>(*this, "test_vec_float", FloatVec{11.0f, 167.23f, 55.66f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a float_vector attribute".
TEST_F(CortexDsrApi, NativeTypesGetAFloatVectorAttribute) {
  get_native<FloatVec>(*this, "test_vec_float", FloatVec{11.0f, 167.23f, 55.66f});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a bool attribute".
TEST_F(CortexDsrApi, NativeTypesInsertABoolAttribute) { insert_native<bool>(*this, "test_bool", true); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a bool attribute".
TEST_F(CortexDsrApi, NativeTypesGetABoolAttribute) { get_native<bool>(*this, "test_bool", true); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a byte_vector attribute"
// (the vector<uint8_t> one).
TEST_F(CortexDsrApi, NativeTypesInsertAByteVectorAttribute) { insert_native<Bytes>(*this, "test_vec_byte", Bytes{11, 167, 55}); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a byte_vector attribute" (uint8_t).
TEST_F(CortexDsrApi, NativeTypesGetAByteVectorAttribute) { get_native<Bytes>(*this, "test_vec_byte", Bytes{11, 167, 55}); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a double attribute".
TEST_F(CortexDsrApi, NativeTypesInsertADoubleAttribute) { insert_native<double>(*this, "test_double", 33.3); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a double attribute".
TEST_F(CortexDsrApi, NativeTypesGetADoubleAttribute) { get_native<double>(*this, "test_double", 33.3); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a byte_vector attribute" (the
// second section of that title, which writes a vector<uint64_t>).
TEST_F(CortexDsrApi, NativeTypesInsertAByteVectorAttributeUInt64Vec) {
  insert_native<UInt64Vec>(*this, "test_vec_u64", UInt64Vec{11, 167, 55});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a byte_vector attribute" (the
// vector<uint64_t> one).
TEST_F(CortexDsrApi, NativeTypesGetAByteVectorAttributeUInt64Vec) {
  get_native<UInt64Vec>(*this, "test_vec_u64", UInt64Vec{11, 167, 55});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 2> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat2Attribute) { insert_native<Vec2f>(*this, "test_vec2", Vec2f{11.0f, 167.0f}); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 2> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat2Attribute) { get_native<Vec2f>(*this, "test_vec2", Vec2f{11.0f, 167.0f}); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 3> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat3Attribute) {
  insert_native<Vec3f>(*this, "test_vec3", Vec3f{11.0f, 167.0f, 0.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 3> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat3Attribute) { get_native<Vec3f>(*this, "test_vec3", Vec3f{11.0f, 167.0f, 0.0f}); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 4> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat4Attribute) {
  insert_native<Vec4f>(*this, "test_vec4", Vec4f{11.0f, 167.0f, 1.0f, 0.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 4> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat4Attribute) {
  get_native<Vec4f>(*this, "test_vec4", Vec4f{11.0f, 167.0f, 1.0f, 0.0f});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 6> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat6Attribute) {
  insert_native<Vec6f>(*this, "test_vec6", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 1.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 6> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat6Attribute) {
  get_native<Vec6f>(*this, "test_vec6", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 1.0f});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 6> attribute
// without reference wrapper" (DSR's by-value accessor; Quiver's get<T> always returns a value).
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat6AttributeWithoutReferenceWrapper) {
  insert_native<Vec6f>(*this, "test_vec6_no_reference", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 0.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 6> attribute" (the
// second section of that title, reading test_vec6_no_reference).
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat6AttributeWithoutReferenceWrapper) {
  get_native<Vec6f>(*this, "test_vec6_no_reference", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 0.0f});
}

}  // namespace
}  // namespace quiver::cortex_tests
