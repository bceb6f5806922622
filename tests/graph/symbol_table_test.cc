// The process's table of names is bounded: filling it refuses new names with an error (it never
// aborts), a message whose names cannot all be added is refused whole, names of a refused message
// are never added, and looking up a name that exists allocates nothing.
// (Its own executable: it fills the table of this process.)

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "graph_test_util.h"
#include "quiver/base/hash.h"
#include "quiver/graph/limits.h"

namespace {
std::atomic<std::size_t> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace quiver::graph {
namespace {

using testing::Peer;

TEST(SymbolTableTest, LookingUpAKnownNameAllocatesNothing) {
  Symbol known("battery");
  const std::size_t before = g_allocations.load();
  for (int i = 0; i < 1000; ++i) {
    Symbol again("battery");
    ASSERT_EQ(again, known);
    ASSERT_EQ(Symbol::find("battery"), known);
  }
  EXPECT_EQ(g_allocations.load(), before);
}

// Each thread keeps its recent lookups by hash (symbol.cc): names that share a slot, looked up in
// turn, and a name never interned whose slot holds another, still get their own answers.
TEST(SymbolTableTest, RecentLookupsThatShareASlotKeepTheirOwnNames) {
  constexpr std::uint64_t kSlots = 256;  // symbol.cc's kRecent
  const std::string first = "slot-a";
  std::string second, absent;
  for (int i = 0; second.empty() || absent.empty(); ++i) {
    const std::string name = "slot-" + std::to_string(i);
    if (name == first || fnv1a64(name) % kSlots != fnv1a64(first) % kSlots) continue;
    (second.empty() ? second : absent) = name;
  }
  const Symbol a(first), b(second);
  ASSERT_NE(a, b);
  for (int round = 0; round < 3; ++round) {
    EXPECT_EQ(Symbol(first), a);
    EXPECT_EQ(Symbol::find(second), b);
    EXPECT_EQ(Symbol(second).str(), second);
    EXPECT_TRUE(Symbol::find(absent).is_null()) << absent << " shares a slot with " << first << " and " << second;
    EXPECT_EQ(Symbol::find(first).str(), first);
  }
}

TEST(SymbolTableTest, NamesOfARefusedMessageAreNeverAdded) {
  Peer a(1);
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.create_node("a_type_nobody_has_seen", "n", {{Symbol("x"), Value(1.0)}}).ok());
  ASSERT_TRUE(tx.commit().ok());
  auto bytes = a.outbox.back();
  bytes.push_back(0);  // a trailing byte: the message is refused
  // The sender interned the type; a fresh name in a refused message must stay unknown here. Use a
  // message from a graph whose type this process has not interned: rename it in the bytes.
  const std::string from = "a_type_nobody_has_seen", to = "b_type_nobody_has_seen";
  auto it = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
  ASSERT_NE(it, bytes.end());
  std::copy(to.begin(), to.end(), it);
  (void)symbols::rt();  // the well-known names are interned once, by whoever first needs them
  const std::size_t count = Symbol::interned_count();
  auto r = decode(bytes);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(Symbol::find(to).is_null()) << "the refused message's name was added";
  EXPECT_EQ(Symbol::interned_count(), count);
  bytes.pop_back();
  ASSERT_TRUE(decode(bytes).ok());
  EXPECT_FALSE(Symbol::find(to).is_null()) << "an accepted message's names are added";
}

// Last: it fills the table of this process.
TEST(SymbolTableTest, AFullTableRefusesNewNamesWithAnError) {
  Peer a(1);
  NodeId x = a.add("thing", "x");
  std::size_t i = 0;
  for (;; ++i) {
    auto s = Symbol::make("filler" + std::to_string(i));
    if (!s.ok()) {
      EXPECT_EQ(s.error().code, ErrorCode::kTooLarge);
      EXPECT_NE(s.error().message.find("full"), std::string::npos) << s.error().message;
      break;
    }
    ASSERT_LT(i, limits::kMaxSymbols + 10) << "the table never filled";
  }
  EXPECT_LE(Symbol::interned_count(), limits::kMaxSymbols);
  // Names already known keep working; new ones are refused by value, not by abort().
  auto tx = a.g.begin();
  EXPECT_TRUE(tx.set(x, "battery", Value(1.0)).ok());
  auto r = tx.set(x, "brand_new_name", Value(1.0));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kTooLarge);
  auto c = tx.create_node("brand_new_type", "y");
  ASSERT_FALSE(c.ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_THROW(Symbol("another_new_name"), std::length_error) << "the constructor reports it too";
  // A peer's delta carrying a new name is refused whole, with the reason.
  GraphDelta d;
  d.kind = GraphDelta::Kind::kDelta;
  d.origin = ReplicaId{9, 1};
  d.context.add_range(d.origin, 1, 1);
  GraphDelta::NodeOp op;
  op.id = NodeId{Dot{d.origin, 1}};
  op.has_header = true;
  op.type = Symbol("thing");  // known
  op.name = "remote";
  d.nodes.push_back(op);
  auto bytes = encode(d);
  const std::string from = "thing", to = "thong";  // same length, unknown
  auto it = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
  ASSERT_NE(it, bytes.end());
  std::copy(to.begin(), to.end(), it);
  auto dec = decode(bytes);
  ASSERT_FALSE(dec.ok());
  EXPECT_EQ(dec.error().code, ErrorCode::kTooLarge);
  EXPECT_NE(dec.error().message.find("full"), std::string::npos) << dec.error().message;
  std::printf("[symbols] the table filled after %zu names\n", i);
}

}  // namespace
}  // namespace quiver::graph
