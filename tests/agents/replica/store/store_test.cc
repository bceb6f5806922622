// The durable store (agents/replica/store): a replica rebuilt from its store equals the one that wrote
// it, rejoins and pulls only what it missed; incarnations are kept only under `always`;
// compaction loses nothing; a damaged or truncated store is refused with an error naming it.

#include "quiver/agents/replica/store/store.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>

#include "quiver/base/hash.h"
#include "test_net.h"

namespace quiver::agents {
namespace {

namespace fs = std::filesystem;
using graph::Value;

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("quiver-store-test-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(counter()++));
    fs::remove_all(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
    for (int n = 1; n < 5; ++n) fs::remove_all(path.string() + ".corrupt-" + std::to_string(n), ec);
  }
  static int& counter() {
    static int c = 0;
    return c;
  }
  std::string str() const { return path.string(); }
};

StoreOptions options(const TempDir& d, Durability dur) {
  StoreOptions o;
  o.dir = d.str();
  o.durability = dur;
  o.batch_ns = 2'000'000;
  o.map_bytes = std::size_t{1} << 30;
  return o;
}

// Adds to `net` a replica that runs from its store, as an agent process does on start.
int add_stored(Net& net, const std::string& name, Store& store) {
  Node n;
  n.g = std::make_unique<Graph>(ReplicaId{fnv1a64(name), store.opening().incarnation});
  auto applied = store.load(*n.g);
  EXPECT_TRUE(applied.ok()) << applied.error().to_string();
  n.port = std::make_unique<Port>();
  n.port->net = &net;
  n.port->index = static_cast<int>(net.nodes.size());
  ReplicatorOptions opt;
  opt.name = name;
  n.rep = std::make_unique<Replicator>(*n.g, *n.port, opt);
  if (applied.ok()) n.rep->restore(*applied);
  n.rep->set_journal(&store);
  n.rep->start(net.now);
  net.nodes.push_back(std::move(n));
  return static_cast<int>(net.nodes.size()) - 1;
}

void write(Graph& g, const std::string& name, int attrs) {
  auto tx = g.begin();
  auto id = tx.create_node("thing", name);
  ASSERT_TRUE(id.ok());
  for (int k = 0; k < attrs; ++k) ASSERT_TRUE(tx.set(*id, "a" + std::to_string(k), Value(double(k))).ok());
  ASSERT_TRUE(tx.commit().ok());
}

void crash(Net& net, int i) {
  net.nodes[i].rep.reset();
  net.nodes[i].g.reset();
}

TEST(StoreTest, AReplicaComesBackFromItsStoreAndPullsOnlyWhatItMissed) {
  TempDir dir;
  Net net;
  int b = net.add(2);
  Digest128 before;
  std::uint64_t first_incarnation = 0;
  {
    auto store = Store::open(options(dir, Durability::kBatch), "robot", 1001);
    ASSERT_TRUE(store.ok()) << store.error().to_string();
    EXPECT_TRUE((*store)->opening().created);
    int a = add_stored(net, "robot", **store);
    first_incarnation = net.nodes[a].g->replica().incarnation;
    net.pump();
    for (int i = 0; i < 200; ++i) write(*net.nodes[i % 2 ? a : b].g, "n" + std::to_string(i), 5);
    net.advance(300'000'000);
    ASSERT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
    before = net.nodes[a].g->digest();
    ASSERT_TRUE((*store)->sync().ok());
    crash(net, a);
  }
  // While it is down, its peer goes on.
  for (int i = 0; i < 10; ++i) write(*net.nodes[b].g, "later" + std::to_string(i), 5);
  net.advance(100'000'000);

  auto store = Store::open(options(dir, Durability::kBatch), "robot", 2002);
  ASSERT_TRUE(store.ok()) << store.error().to_string();
  EXPECT_FALSE((*store)->opening().created);
  EXPECT_FALSE((*store)->opening().incarnation_kept) << "under batch a published dot may be lost";
  EXPECT_EQ((*store)->opening().incarnation, 2002u);
  Graph check(ReplicaId{fnv1a64("robot"), 2002});
  ASSERT_TRUE((*store)->load(check).ok());
  EXPECT_EQ(check.digest(), before) << "the store holds the replica as it was";
  EXPECT_EQ(check.node_count(), 200u);

  int a = add_stored(net, "robot", **store);
  EXPECT_NE(net.nodes[a].g->replica().incarnation, first_incarnation);
  net.advance(500'000'000);
  EXPECT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
  EXPECT_EQ(net.nodes[a].g->node_count(), 210u);
  const auto& st = net.nodes[a].rep->stats();
  // It pulled the 10 changes it missed, not the 200 it had.
  EXPECT_LE(st.state_bytes_received, 20'000u) << "pulled " << st.state_bytes_received << " bytes";
  EXPECT_LE(st.deltas_applied + st.states_applied, 20u);
}

TEST(StoreTest, UnderAlwaysTheReplicaKeepsItsIncarnationAndItsNumbers) {
  TempDir dir;
  Net net;
  int b = net.add(2);
  std::uint64_t inc = 0, seq = 0;
  {
    auto store = Store::open(options(dir, Durability::kAlways), "arm", 77);
    ASSERT_TRUE(store.ok());
    int a = add_stored(net, "arm", **store);
    net.pump();
    for (int i = 0; i < 20; ++i) write(*net.nodes[a].g, "n" + std::to_string(i), 2);
    net.advance(200'000'000);
    inc = net.nodes[a].g->replica().incarnation;
    seq = net.nodes[a].rep->last_seq();
    EXPECT_EQ(seq, 20u);
    EXPECT_EQ((*store)->stats().syncs, 21u) << "one flush per commit, plus the one at open";
    crash(net, a);  // no sync(): under always every commit is on disk when it returns
  }
  auto store = Store::open(options(dir, Durability::kAlways), "arm", 99);
  ASSERT_TRUE(store.ok());
  EXPECT_TRUE((*store)->opening().incarnation_kept);
  EXPECT_EQ((*store)->opening().incarnation, inc);
  int a = add_stored(net, "arm", **store);
  EXPECT_EQ(net.nodes[a].rep->last_seq(), seq) << "numbering goes on after the last published delta";
  write(*net.nodes[a].g, "after", 1);
  EXPECT_EQ(net.nodes[a].rep->last_seq(), seq + 1);
  net.advance(300'000'000);
  EXPECT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
  EXPECT_EQ(net.nodes[b].g->node_count(), 21u);
  EXPECT_TRUE(net.nodes[b].errors.empty()) << net.nodes[b].errors.front().to_string();
  EXPECT_EQ(net.nodes[b].rep->stats().equivocations, 0u) << "no number was used twice";

  // A run under batch ends the proof: the next start takes a new incarnation.
  crash(net, a);
  store->reset();
  auto batch = Store::open(options(dir, Durability::kBatch), "arm", 100);
  ASSERT_TRUE(batch.ok());
  EXPECT_TRUE((*batch)->opening().incarnation_kept) << "the runs so far were all under always";
  batch->reset();
  auto again = Store::open(options(dir, Durability::kAlways), "arm", 101);
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE((*again)->opening().incarnation_kept);
  EXPECT_EQ((*again)->opening().incarnation, 101u);
}

TEST(StoreTest, CompactionFoldsTheLogIntoASnapshotAndLosesNothing) {
  TempDir dir;
  auto opt = options(dir, Durability::kBatch);
  opt.compact_log_bytes = 16 << 10;
  Net net;
  Digest128 before;
  {
    auto store = Store::open(opt, "robot", 5);
    ASSERT_TRUE(store.ok());
    int a = add_stored(net, "robot", **store);
    int b = net.add(2);
    net.pump();
    for (int i = 0; i < 600; ++i) {
      write(*net.nodes[i % 3 ? a : b].g, "n" + std::to_string(i), 4);
      if (i % 50 == 0) net.advance(10'000'000, 1);
    }
    net.advance(300'000'000);
    ASSERT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
    before = net.nodes[a].g->digest();
    ASSERT_TRUE((*store)->compact().ok());
    ASSERT_TRUE((*store)->health().ok());
    EXPECT_GE((*store)->stats().compactions, 1u);
    crash(net, a);
  }
  auto store = Store::open(opt, "robot", 6);
  ASSERT_TRUE(store.ok());
  EXPECT_GT((*store)->opening().snapshot_bytes, 0u);
  Graph g(ReplicaId{fnv1a64("robot"), 6});
  ASSERT_TRUE((*store)->load(g).ok());
  EXPECT_EQ(g.digest(), before);
  EXPECT_EQ((*store)->opening().records, 0u) << "everything was folded into the snapshot";
  EXPECT_TRUE(g.check_invariants().empty());
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_file(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << s;
}

TEST(StoreTest, ADamagedRecordIsNamedAndTheStoreCanBeSetAside) {
  TempDir dir;
  const std::string marker = "MARKER-0123456789-abcdefghij";
  {
    auto store = Store::open(options(dir, Durability::kBatch), "robot", 5);
    ASSERT_TRUE(store.ok());
    Net net;
    int a = add_stored(net, "robot", **store);
    for (int i = 0; i < 5; ++i) write(*net.nodes[a].g, "n" + std::to_string(i), 1);
    auto tx = net.nodes[a].g->begin();
    auto id = tx.create_node("thing", "marked");
    ASSERT_TRUE(id.ok());
    ASSERT_TRUE(tx.set(*id, "note", Value(marker)).ok());
    ASSERT_TRUE(tx.commit().ok());
    write(*net.nodes[a].g, "after", 1);  // the damaged record is not the last (that one is a torn write)
    ASSERT_TRUE((*store)->sync().ok());
  }
  const fs::path data = dir.path / "data.mdb";
  std::string bytes = read_file(data);
  const auto at = bytes.find(marker);
  ASSERT_NE(at, std::string::npos);
  bytes[at + 3] ^= 0x20;
  write_file(data, bytes);

  auto store = Store::open(options(dir, Durability::kBatch), "robot", 6);
  ASSERT_TRUE(store.ok()) << "the meta records are intact";
  Graph g(ReplicaId{fnv1a64("robot"), 6});
  auto loaded = (*store)->load(g);
  ASSERT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.error().code, ErrorCode::kMalformed);
  EXPECT_NE(loaded.error().message.find("log record 6"), std::string::npos) << loaded.error().message;
  EXPECT_NE(loaded.error().message.find("checksum"), std::string::npos) << loaded.error().message;
  EXPECT_NE(loaded.error().message.find(dir.str()), std::string::npos) << loaded.error().message;
  store->reset();
  auto aside = Store::set_aside(dir.str());
  ASSERT_TRUE(aside.ok());
  EXPECT_TRUE(fs::exists(fs::path(*aside) / "data.mdb"));
  auto fresh = Store::open(options(dir, Durability::kBatch), "robot", 7);
  ASSERT_TRUE(fresh.ok());
  EXPECT_TRUE((*fresh)->opening().created);
}

TEST(StoreTest, ATruncatedFileIsRefusedBeforeItIsRead) {
  TempDir dir;
  {
    auto store = Store::open(options(dir, Durability::kBatch), "robot", 5);
    ASSERT_TRUE(store.ok());
    Net net;
    int a = add_stored(net, "robot", **store);
    for (int i = 0; i < 300; ++i) write(*net.nodes[a].g, "n" + std::to_string(i), 8);
    ASSERT_TRUE((*store)->sync().ok());
  }
  const fs::path data = dir.path / "data.mdb";
  const auto size = fs::file_size(data);
  ASSERT_GT(size, 64u << 10);
  fs::resize_file(data, size / 2);
  auto store = Store::open(options(dir, Durability::kBatch), "robot", 6);
  ASSERT_FALSE(store.ok());
  EXPECT_EQ(store.error().code, ErrorCode::kTruncated) << store.error().to_string();
  EXPECT_NE(store.error().message.find(dir.str()), std::string::npos) << store.error().message;
}

TEST(StoreTest, OneProcessOneAgentPerStore) {
  TempDir dir;
  auto first = Store::open(options(dir, Durability::kNone), "robot", 5);
  ASSERT_TRUE(first.ok());
  auto second = Store::open(options(dir, Durability::kNone), "robot", 6);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, ErrorCode::kAlreadyExists);
  first->reset();
  auto other = Store::open(options(dir, Durability::kNone), "camera", 6);
  ASSERT_FALSE(other.ok());
  EXPECT_EQ(other.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(other.error().message.find("belongs to agent 'robot'"), std::string::npos) << other.error().message;
  EXPECT_FALSE(parse_durability("sometimes").ok());
  EXPECT_EQ(*parse_durability("always"), Durability::kAlways);
}

}  // namespace
}  // namespace quiver::agents
