// The agent engine's parts: timers, the watch of user code and the keeper that reads it, jobs,
// tasks posted from other threads within a turn's budget, and a bare replica stepped by it.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/agents/runtime/engine/liveness_keeper.h"
#include "test_net.h"

namespace quiver::agents {
namespace {

TEST(EngineTest, TimersRunInDueOrderAndAPeriodThatFellBehindRunsOnce) {
  TimerQueue q;
  std::vector<int> ran;
  q.at(30, [&] { ran.push_back(3); });
  q.at(10, [&] { ran.push_back(1); });
  TimerId cancelled = q.at(20, [&] { ran.push_back(2); });
  q.cancel(cancelled);
  int ticks = 0;
  q.every(5, 10, [&] { ++ticks; });
  EXPECT_EQ(q.next_due(), 5);
  q.run_due(30);
  EXPECT_EQ(ran, (std::vector<int>{1, 3}));
  EXPECT_EQ(ticks, 1) << "due at 5, 15 and 25: a round at 30, a whole period behind, runs it once";
  EXPECT_EQ(q.next_due(), 40) << "and starts the period again from then";
  ticks = 0;
  q.run_due(1000);  // far behind: once, and the period starts again from 1000
  EXPECT_EQ(ticks, 1);
  EXPECT_EQ(q.next_due(), 1010);
  // A budget stops the round after the first timer; the rest wait.
  int a = 0;
  q.at(1005, [&] { ++a; });
  q.at(1006, [&] { ++a; });
  q.run_due(1100, [] { return false; });
  EXPECT_EQ(a + ticks, 2) << "one more timer ran (a budget never stops the first)";
}

TEST(EngineTest, AWatchSeesTheOutermostCallFromAnotherThread) {
  CallbackWatch w("speech");
  const std::string action = "say";
  EXPECT_FALSE(w.snapshot().busy);
  std::uint64_t call = 0;
  {
    auto outer = w.enter("process()", &action, 100);
    {
      auto inner = w.enter("a subscription", nullptr, 150);  // nested: the outer call stays
      CallbackWatch::Snapshot s;
      std::thread([&] { s = w.snapshot(); }).join();
      EXPECT_TRUE(s.busy);
      EXPECT_EQ(s.since_ns, 100);
      EXPECT_STREQ(s.callback, "process()");
      EXPECT_EQ(s.action, "say");
      call = s.call;
    }
    EXPECT_TRUE(w.snapshot().busy);
  }
  EXPECT_FALSE(w.snapshot().busy);
  auto next = w.enter("a timer", nullptr, 200);
  EXPECT_EQ(w.snapshot().call, call + 1);
  EXPECT_EQ(describe_callback(w.snapshot()), "a timer");
}

TEST(EngineTest, TheKeeperBeatsForABlockedCallbackAndReportsItOnce) {
  CallbackWatch w("speech");
  const std::string action = "say";
  std::atomic<std::int64_t> now{0};
  std::atomic<int> beats{0};
  std::mutex mu;
  std::vector<std::string> warnings, infos;
  KeeperOptions o;
  o.beat_ns = 20'000'000;
  o.hang_ns = 200'000'000;
  o.clock = [&] { return now.load(); };
  auto wait_for = [&](auto pred) {
    for (int i = 0; i < 2000 && !pred(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return pred();
  };
  {
    LivenessKeeper k(
        w, o, [&] { ++beats; },
        [&](const std::string& l) {
          std::lock_guard<std::mutex> g(mu);
          warnings.push_back(l);
        },
        [&](const std::string& l) {
          std::lock_guard<std::mutex> g(mu);
          infos.push_back(l);
        });
    // Not in user code: nothing to do, however much time passes.
    now = 10'000'000'000;
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    EXPECT_EQ(beats.load(), 0);
    {
      auto in = w.enter("process()", &action, now.load());
      now += 50'000'000;  // blocked for 50 ms: beats, not yet hung
      EXPECT_TRUE(wait_for([&] { return beats.load() >= 1; }));
      now += 500'000'000;  // 550 ms: hung
      EXPECT_TRUE(wait_for([&] {
        std::lock_guard<std::mutex> g(mu);
        return !warnings.empty();
      }));
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
    }
    now += 10'000'000;
    EXPECT_TRUE(wait_for([&] {
      std::lock_guard<std::mutex> g(mu);
      return !infos.empty();
    }));
    EXPECT_EQ(k.hangs(), 1u);
  }
  ASSERT_EQ(warnings.size(), 1u) << "one report per hung call";
  EXPECT_NE(warnings[0].find("agent 'speech': action 'say' process() has not returned"), std::string::npos)
      << warnings[0];
  EXPECT_NE(infos[0].find("came back"), std::string::npos) << infos[0];
}

TEST(EngineTest, AJobWorksOffTheEnginesThreadAndFinishesOnIt) {
  graph::Graph g(graph::ReplicaId{1, 1});
  EngineOptions o;
  o.clock = [] { return std::chrono::steady_clock::now().time_since_epoch().count(); };
  Engine e(g, nullptr, o);
  const auto self = std::this_thread::get_id();
  std::thread::id worker;
  std::atomic<bool> done{false};
  e.run_job([&] { worker = std::this_thread::get_id(); },
            [&] {
              EXPECT_EQ(std::this_thread::get_id(), self) << "done() runs on the engine's thread";
              done = true;
            });
  for (int i = 0; i < 2000 && !done; ++i) {
    e.run_posted();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(done);
  EXPECT_NE(worker, self) << "work() ran on the worker";
  // Inline (the simulator): work at once, done at the next round.
  EngineOptions inl = o;
  inl.jobs = JobRunner::Mode::kInline;
  Engine e2(g, nullptr, inl);
  int step = 0;
  e2.run_job([&] { step = 1; }, [&] { step = 2; });
  EXPECT_EQ(step, 1);
  e2.run_posted();
  EXPECT_EQ(step, 2);
}

TEST(EngineTest, PostedTasksBeyondTheTurnsBudgetWaitForTheNextRound) {
  graph::Graph g(graph::ReplicaId{1, 1});
  std::int64_t now = 0;
  EngineOptions o;
  o.clock = [&] { return now; };
  o.turn_budget_ns = 10;
  Engine e(g, nullptr, o);
  int ran = 0;
  for (int i = 0; i < 5; ++i)
    e.post([&] {
      ++ran;
      now += 6;  // each task takes 6 ns: two fit in a turn of 10
    });
  EXPECT_TRUE(e.tasks_waiting());
  e.run_posted();
  EXPECT_EQ(ran, 2);
  EXPECT_EQ(e.stats().turns_over_budget, 1u);
  e.run_posted();
  e.run_posted();
  EXPECT_EQ(ran, 5);
  EXPECT_FALSE(e.tasks_waiting());
  // call() from another thread returns the value once the engine's thread runs it.
  std::future<int> f;
  std::thread other([&] { f = e.call([] { return 42; }); });
  other.join();
  e.run_posted();
  EXPECT_EQ(f.get(), 42);
}

TEST(EngineTest, ABareReplicaIsSteppedByItsEngine) {
  Net net;
  int a = net.add(1), b = net.add(2);
  std::int64_t now = 0;
  EngineOptions o;
  o.clock = [&] { return net.now; };
  o.locks_enabled = true;
  Engine e(*net.nodes[a].g, net.nodes[a].rep.get(), o);
  ASSERT_TRUE(e.start().ok());
  ASSERT_NE(e.lock_manager(), nullptr);
  for (int i = 0; i < 30; ++i) {
    net.now += 10'000'000;
    net.nodes[b].rep->tick(net.now);
    e.step();  // heartbeats, pulls and liveness of a's replicator, and its locks' upkeep
    net.pump();
  }
  (void)now;
  EXPECT_EQ(net.nodes[b].rep->live_peer_count(), 1u) << "b hears a: its engine sends its heartbeats";
  EXPECT_EQ(net.nodes[a].rep->live_peer_count(), 1u);
}

// A peer's change that this agent's grammar does not verify is a warning, naming the peer, and
// says when no grammar was given for that peer (its changes are then checked with this agent's).
TEST(EngineTest, AnUnverifiedChangeOfAPeerIsAWarningNamingIt) {
  Net net;
  const int a = net.add(1), b = net.add(2);
  EngineOptions o;
  o.clock = [&] { return net.now; };
  o.grammar_text = R"(grammar unary
types { robot }
rule startMoving : active { { r:robot  !r->r(moving) } => { r:robot  r->r(moving) } }
)";
  o.grammar_source = "unary.aggl";
  std::vector<std::string> info, warnings;
  o.log = [&](std::string_view line) { info.emplace_back(line); };
  o.warn = [&](std::string_view line) { warnings.emplace_back(line); };
  Engine e(*net.nodes[a].g, net.nodes[a].rep.get(), o);
  ASSERT_TRUE(e.start().ok());
  net.nodes[a].g->set_origin_namer([](const graph::ReplicaId& r, std::string& name) { name = "agent" + std::to_string(r.agent); });
  add_node(*net.nodes[b].g, "robot");  // b has no grammar: its commit claims no rule
  net.pump();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("a change from agent2 ("), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("no grammar given for that agent"), std::string::npos) << warnings[0];
  EXPECT_TRUE(info.empty());
}

}  // namespace
}  // namespace quiver::agents
