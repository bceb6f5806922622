// The DSR-style agent surface (docs/dsr-api.md): DdsReplica::call() returning a future, its
// timers, change batches naming the origin agent over DDS (loopback), and Agent::call() through
// the runtime.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/runtime/engine/engine.h"

namespace quiver::agents {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::uint32_t kDomain = 201;  // distinct from the other DDS tests' domains

std::unique_ptr<DdsReplica> make_replica(const std::string& name) {
  DdsReplicaOptions o;
  o.name = name;
  o.dds.domain = kDomain;
  o.dds.own_domain_instance = true;
  o.replicator.heartbeat_ns = 50 * kMs;
  auto r = DdsReplica::create(o);
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  return r.ok() ? std::move(*r) : nullptr;
}

struct Spinning {
  std::unique_ptr<DdsReplica> replica;
  std::thread thread;
  explicit Spinning(std::unique_ptr<DdsReplica> r) : replica(std::move(r)) {
    DdsReplica* raw = replica.get();
    thread = std::thread([raw] { raw->spin(); });
  }
  ~Spinning() {
    replica->stop();
    thread.join();
  }
};

TEST(DdsReplicaApi, CallReturnsAFutureFromTheOwnerThread) {
  auto r = make_replica("caller");
  ASSERT_TRUE(r);
  Spinning s(std::move(r));
  const std::thread::id main_thread = std::this_thread::get_id();
  auto on_owner = s.replica->call([&] { return std::this_thread::get_id() != main_thread; });
  EXPECT_TRUE(on_owner.get());
  auto created = s.replica->call([&] {
    auto tx = s.replica->graph().begin();
    auto id = tx.create_node("robot", "robot", {{"speed", 4}});
    EXPECT_TRUE(tx.commit().ok());
    return id.value();
  });
  const graph::NodeId robot = created.get();
  std::future<std::int64_t> speed =
      s.replica->call([&] { return s.replica->graph().get<std::int64_t>(robot, "speed").value(); });
  EXPECT_EQ(speed.get(), 4);
  std::future<void> thrown = s.replica->call([] { throw std::runtime_error("boom"); });
  EXPECT_THROW(thrown.get(), std::runtime_error);
}

TEST(DdsReplicaApi, TimersRunOnTheOwnerThread) {
  auto r = make_replica("timers");
  ASSERT_TRUE(r);
  Spinning s(std::move(r));
  std::atomic<int> once{0}, periodic{0}, cancelled{0};
  s.replica
      ->call([&] {
        s.replica->after(20 * kMs, [&] { ++once; });
        DdsReplica::TimerId dead = s.replica->after(30 * kMs, [&] { ++cancelled; });
        s.replica->cancel(dead);
        // A periodic timer that cancels itself on its fifth run.
        auto id = std::make_shared<DdsReplica::TimerId>(0);
        *id = s.replica->every(10 * kMs, [&, id] {
          if (++periodic == 5) s.replica->cancel(*id);
        });
      })
      .get();
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  EXPECT_EQ(once.load(), 1);
  EXPECT_EQ(cancelled.load(), 0);
  EXPECT_EQ(periodic.load(), 5);
}

TEST(DdsReplicaApi, ChangeBatchesNameTheOriginAgent) {
  auto ra = make_replica("alice");
  auto rb = make_replica("bob");
  ASSERT_TRUE(ra && rb);
  Spinning a(std::move(ra)), b(std::move(rb));
  std::mutex mu;
  std::vector<std::pair<std::string, bool>> heard;  // (origin_name, local) at bob
  b.replica
      ->call([&] {
        b.replica->graph().subscribe([&](const graph::ChangeBatch& batch) {
          std::lock_guard<std::mutex> lock(mu);
          heard.emplace_back(batch.origin_name, batch.local);
        });
      })
      .get();
  // Wait until they know each other, then write on both sides.
  const std::int64_t end = monotonic_ns() + 5000 * kMs;
  while (monotonic_ns() < end && !(a.replica->call([&] { return a.replica->replicator().live_peer_count(); }).get() > 0 &&
                                    b.replica->call([&] { return b.replica->replicator().live_peer_count(); }).get() > 0))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  a.replica
      ->call([&] {
        auto tx = a.replica->graph().begin();
        EXPECT_TRUE(tx.create_node("person", "patient").ok());
        EXPECT_TRUE(tx.commit().ok());
      })
      .get();
  b.replica
      ->call([&] {
        auto tx = b.replica->graph().begin();
        EXPECT_TRUE(tx.create_node("chair", "chair").ok());
        EXPECT_TRUE(tx.commit().ok());
      })
      .get();
  bool got = false;
  const std::int64_t end2 = monotonic_ns() + 5000 * kMs;
  while (!got && monotonic_ns() < end2) {
    {
      std::lock_guard<std::mutex> lock(mu);
      for (const auto& [name, local] : heard) got = got || (name == "alice" && !local);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::lock_guard<std::mutex> lock(mu);
  EXPECT_TRUE(got) << "bob never heard a change named 'alice'";
  bool own = false;
  for (const auto& [name, local] : heard) own = own || (name == "bob" && local);
  EXPECT_TRUE(own);
  EXPECT_EQ(b.replica->replicator().name_of(a.replica->id()), "alice");
  const graph::ReplicaId stranger{12345, 1};
  EXPECT_EQ(b.replica->replicator().name_of(stranger), stranger.to_string());
}

// A minimal agent for the runtime: no grammar, no actions.
class Idle final : public Agent {
 public:
  Idle() : Agent("idle") {}
  void setup(AgentContext&) override {}
};

TEST(AgentApi, CallRunsOnTheHostTickAndReturnsAFuture) {
  graph::Graph g(graph::ReplicaId{fnv1a64("idle"), 1});
  Idle agent;
  std::int64_t now = 0;
  RuntimeOptions options;
  options.clock = [&] { return now; };
  AgentRuntime rt(agent, g, nullptr, options);
  ASSERT_TRUE(rt.start().ok());
  std::future<std::size_t> nodes;
  std::thread other([&] {
    nodes = agent.call([&] {
      auto tx = g.begin();
      EXPECT_TRUE(tx.create_node("robot", "robot").ok());
      EXPECT_TRUE(tx.commit().ok());
      return g.node_count();
    });
  });
  other.join();
  EXPECT_EQ(nodes.wait_for(std::chrono::seconds(0)), std::future_status::timeout);  // not yet: no tick
  rt.tick();
  ASSERT_EQ(nodes.wait_for(std::chrono::seconds(0)), std::future_status::ready);
  EXPECT_EQ(nodes.get(), 1u);
  // Timers of the agent API (AgentContext::after/every) run on ticks too.
  int fired = 0;
  rt.every(10, [&] { ++fired; });
  now = 25;
  rt.tick();
  EXPECT_EQ(fired, 1);
  rt.stop();
}

}  // namespace
}  // namespace quiver::agents
