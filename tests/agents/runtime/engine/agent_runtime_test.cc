// The agent runtime on replicas joined by the hand-driven network: the DSR loop (find, lock,
// start, process, finish), cancellation when the precondition goes or the lock is lost, timers
// on the host's clock, and filtered subscriptions.

#include "quiver/agents/runtime/engine/engine.h"

#include <gtest/gtest.h>

#include "test_net.h"

namespace quiver::agents {
namespace {

using graph::NodeId;
using graph::Value;

std::string state_of(Graph& g, NodeId n) {
  const Value* v = g.attr(n, "state");
  return v && v->get_if<std::string>() ? *v->get_if<std::string>() : "";
}

// Serves "request" nodes: marks them executing, works for `work_ns`, marks them done; a request
// whose "cancel" attribute is set, or whose lock is taken, is cancelled.
class Server : public Agent {
 public:
  Server(std::int64_t work_ns, std::int64_t priority) : Agent("server") {
    struct Serve : Action {
      Server* self;
      explicit Serve(Server* s) : Action("serve"), self(s) {}
      std::vector<Match> find(AgentContext& ctx) override {
        std::vector<Match> out;
        for (NodeId n : ctx.graph().nodes_of_type("request"))
          if (state_of(ctx.graph(), n) == "new") out.push_back(Match{n.to_string(), {{"request", n}}});
        return out;
      }
      bool holds(AgentContext& ctx, const Match& m) override {
        return ctx.graph().has_node(m.at("request")) && ctx.graph().attr(m.at("request"), "cancel") == nullptr;
      }
      std::optional<LockNeed> lock(AgentContext&, const Match& m) override {
        return LockNeed{m.at("request"), self->priority_};
      }
      Status start(AgentContext& ctx, const Match& m) override {
        started_at = ctx.now();
        auto tx = ctx.graph().begin();
        if (Status s = tx.set(m.at("request"), "state", Value("executing")); !s.ok()) return s;
        auto c = tx.commit();
        return c.ok() ? Status{} : Status(c.error());
      }
      Progress process(AgentContext& ctx, const Match&) override {
        return ctx.now() - started_at >= self->work_ns_ ? Progress::kDone : Progress::kRunning;
      }
      Status finish(AgentContext& ctx, const Match& m) override {
        auto tx = ctx.graph().begin();
        (void)tx.set(m.at("request"), "state", Value("done"));
        auto c = tx.commit();
        return c.ok() ? Status{} : Status(c.error());
      }
      void cancel(AgentContext& ctx, const Match& m, CancelReason why) override {
        self->cancelled.push_back(why);
        if (!ctx.graph().has_node(m.at("request")) || why == CancelReason::kLockLost) return;
        auto tx = ctx.graph().begin();
        (void)tx.set(m.at("request"), "state", Value("cancelled"));
        (void)tx.commit();
      }
      std::int64_t started_at = 0;
    };
    add_action(std::make_unique<Serve>(this), ChangeFilter{{"request"}, {}, {"state", "cancel"}});
    work_ns_ = work_ns;
    priority_ = priority;
  }
  void setup(AgentContext& ctx) override {
    ctx.every(100'000'000, [this] { ++heartbeats; });
  }
  std::int64_t work_ns_ = 0, priority_ = 1;
  std::vector<CancelReason> cancelled;
  int heartbeats = 0;
};

struct Rig {
  Net net;
  int a = 0, b = 0;
  Server server{300'000'000, 1};
  std::unique_ptr<AgentRuntime> rt;
  std::vector<ActionEvent> events;

  Rig() {
    ReplicatorOptions ro;
    ro.heartbeat_ns = 20'000'000;
    ro.lease_ns = 500'000'000;
    a = net.add(1, ro);
    b = net.add(2, ro);
    RuntimeOptions o;
    o.clock = [this] { return net.now; };
    rt = std::make_unique<AgentRuntime>(server, *net.nodes[a].g, net.nodes[a].rep.get(), o);
    rt->on_action_event([this](const ActionEvent& e) { events.push_back(e); });
    EXPECT_TRUE(rt->start().ok());
    step(100'000'000);
  }
  // Advances time in 10 ms ticks, delivering packets and running the agent's host loop.
  void step(std::int64_t ns) {
    for (std::int64_t t = 0; t < ns; t += 10'000'000) {
      net.advance(10'000'000, 1);
      rt->pump();
      rt->tick();
      net.pump();
      rt->pump();
    }
  }
  NodeId request(const std::string& name) {
    auto tx = net.nodes[b].g->begin();
    NodeId n = *tx.create_node("request", name, {{graph::Symbol("state"), Value("new")}});
    EXPECT_TRUE(tx.commit().ok());
    return n;
  }
};

TEST(RuntimeTest, TheDsrLoopRunsAnActionFromFindToFinish) {
  Rig r;
  NodeId req = r.request("r1");
  r.step(100'000'000);
  EXPECT_EQ(state_of(*r.net.nodes[r.b].g, req), "executing") << "the mark is a change the other agent sees";
  r.step(400'000'000);
  EXPECT_EQ(state_of(*r.net.nodes[r.b].g, req), "done");
  ASSERT_GE(r.events.size(), 3u);
  EXPECT_EQ(r.events[0].kind, ActionEvent::Kind::kWaitingLock);
  EXPECT_EQ(r.events[1].kind, ActionEvent::Kind::kStarted);
  EXPECT_EQ(r.events.back().kind, ActionEvent::Kind::kFinished);
  EXPECT_EQ(r.rt->stats().finished, 1u);
  EXPECT_TRUE(r.rt->runs().empty());
  EXPECT_FALSE(r.rt->locks().holds(req)) << "the lock goes with the run";
  EXPECT_GE(r.server.heartbeats, 5) << "timers run on the host's clock";
}

TEST(RuntimeTest, AnActionWhosePreconditionGoesIsCancelledAtOnce) {
  Rig r;
  NodeId req = r.request("r1");
  r.step(100'000'000);
  ASSERT_EQ(state_of(*r.net.nodes[r.b].g, req), "executing");
  auto tx = r.net.nodes[r.b].g->begin();
  ASSERT_TRUE(tx.set(req, "cancel", Value(true)).ok());
  ASSERT_TRUE(tx.commit().ok());
  const std::int64_t sent = r.net.now;
  r.net.pump();
  r.rt->pump();  // the merge is handled: the precondition is checked before any tick
  ASSERT_EQ(r.server.cancelled.size(), 1u);
  EXPECT_EQ(r.server.cancelled[0], CancelReason::kPreconditionGone);
  EXPECT_EQ(r.net.now, sent) << "cancelled in the same host round as the change arrived";
  r.step(50'000'000);
  EXPECT_EQ(state_of(*r.net.nodes[r.b].g, req), "cancelled");
}

TEST(RuntimeTest, AnActionWhoseLockIsTakenByAHigherPriorityIsCancelled) {
  Rig r;
  LockManager other(*r.net.nodes[r.b].g, r.net.nodes[r.b].rep.get(), [&] { return r.net.now; });
  other.install();
  NodeId req = r.request("r1");
  r.step(100'000'000);
  ASSERT_EQ(state_of(*r.net.nodes[r.b].g, req), "executing");
  ASSERT_TRUE(other.acquire(req, 5).ok());
  for (int i = 0; i < 20 && r.server.cancelled.empty(); ++i) {
    r.step(10'000'000);
    other.tick();
  }
  ASSERT_EQ(r.server.cancelled.size(), 1u);
  EXPECT_EQ(r.server.cancelled[0], CancelReason::kLockLost);
  EXPECT_EQ(r.events.back().kind, ActionEvent::Kind::kCancelled);
  EXPECT_EQ(r.events.back().reason, CancelReason::kLockLost);
}

TEST(RuntimeTest, SubscriptionsSeeOnlyWhatTheirFilterSelects) {
  Net net;
  int a = net.add(1);
  struct Watcher : Agent {
    Watcher() : Agent("watcher") {}
    void setup(AgentContext&) override {
      subscribe(ChangeFilter{{"person"}, {}, {}}, [this](AgentContext&, const graph::ChangeBatch& b) {
        for (const auto& n : b.nodes) persons.push_back(n.type.str());
      });
      subscribe(ChangeFilter{{}, {}, {"battery"}}, [this](AgentContext&, const graph::ChangeBatch& b) {
        batteries += static_cast<int>(b.nodes.size());
      });
    }
    std::vector<std::string> persons;
    int batteries = 0;
  } w;
  AgentRuntime rt(w, *net.nodes[a].g, nullptr, RuntimeOptions{1, {}, 100'000'000, [&] { return net.now; }, nullptr});
  ASSERT_TRUE(rt.start().ok());
  auto tx = net.nodes[a].g->begin();
  NodeId robot = *tx.create_node("robot", "robot");
  (void)tx.create_node("person", "carlos");
  ASSERT_TRUE(tx.commit().ok());
  auto tx2 = net.nodes[a].g->begin();
  (void)tx2.set(robot, "battery", Value(0.5));
  (void)tx2.set(robot, "speed", Value(1.0));
  ASSERT_TRUE(tx2.commit().ok());
  rt.pump();
  EXPECT_EQ(w.persons, std::vector<std::string>{"person"});
  EXPECT_EQ(w.batteries, 1);
}

TEST(RuntimeTest, AGrammarThatDoesNotParseStopsTheStartWithItsPlace) {
  Net net;
  int a = net.add(1);
  struct Bad : Agent {
    Bad() : Agent("bad") { set_grammar_text("grammar g\nrule x : active { { a:t } => { a:t b:} }\n", "bad.aggl"); }
    void setup(AgentContext&) override {}
  } bad;
  AgentRuntime rt(bad, *net.nodes[a].g, nullptr, RuntimeOptions{1, {}, 100'000'000, [&] { return net.now; }, nullptr});
  Status s = rt.start();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("bad.aggl:"), std::string::npos) << s.error().message;
}

}  // namespace
}  // namespace quiver::agents
