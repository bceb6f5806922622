#pragma once
/// @file
/// The agent API. An agent is a class: a name, a grammar file that its changes must follow, the
/// lock priorities it uses, filtered subscriptions to changes, timers, and actions (action.h),
/// declared in setup(). It never talks to another agent: it reads the graph, acts, and writes.
///
/// The same class runs unchanged in either host:
///  - an OS process over Cyclone DDS: `quiver::agents::run_process(agent, argc, argv)` or
///    `quiver run ROLE` (process_host.h);
///  - the deterministic simulator, many at once, with virtual time and faults
///    (`quiver sim --scenario FILE`, sim/scenario.h).
///
/// Threading: everything an agent does happens on its host's thread, one call at a time.
/// Only post() and call() may be called from other threads.

#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <type_traits>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "quiver/agents/runtime/api/posted_call.h"
#include "quiver/agents/runtime/api/action.h"
#include "quiver/agents/runtime/api/context.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline runtime {

/// Which changes a subscription cares about (node types, edge types, attribute names): the
/// graph's filter, also usable without an agent (Graph::subscribe(filter, cb)).
using ChangeFilter = graph::ChangeFilter;

class Agent {
 public:
  /// An agent called `name`: its replica id derives from it (fnv1a64), so names must be
  /// unique among the agents that meet.
  explicit Agent(std::string name) : name_(std::move(name)) {}
  /// @pre Its host no longer runs it.
  virtual ~Agent() = default;
  Agent(const Agent&) = delete;
  Agent& operator=(const Agent&) = delete;

  /// @returns the name given to the constructor. Any thread.
  const std::string& name() const { return name_; }

  /// Declares subscriptions, actions and timers. Called once by the host, with the replica
  /// joined to its peers (or alone after a short wait). On the host's thread, after the grammar
  /// and lock checks are installed.
  virtual void setup(AgentContext& ctx) = 0;
  /// Called on every host tick, after timers and actions: about every 10 ms, and every 100 ms
  /// while a process's replica has been quiet for half a second (DdsReplicaOptions::quiet_tick_ns;
  /// use AgentContext::every() for a steady period). Host's thread.
  virtual void on_tick(AgentContext& ctx) {}
  /// Called once when the host stops (running actions have been cancelled). Host's thread.
  virtual void teardown(AgentContext& ctx) {}
  /// Adds the agent's own fields to the host's status lines (e.g. what it is doing).
  /// Host's thread; `out` is a JSON object.
  virtual void status(nlohmann::json& out) const {}

  // ---- declarations (in the constructor or setup()) ----

  /// Every change this agent commits must be one rule application of this grammar
  /// (docs/grammar.md). Empty: no grammar check. Read by the host's start(), so it takes effect
  /// only when set in the constructor (setup() runs after the grammar is loaded). Host's thread.
  void set_grammar_file(std::string path) { grammar_file_ = std::move(path); }
  /// @returns the grammar file's path ("" if none).
  const std::string& grammar_file() const { return grammar_file_; }
  /// Grammar text given inline (e.g. embedded), checked like a file named `source`.
  /// Wins over set_grammar_file(); set it in the constructor, as that. Host's thread.
  void set_grammar_text(std::string text, std::string source) {
    grammar_text_ = std::move(text);
    grammar_source_ = std::move(source);
  }
  /// @returns the inline grammar text ("" if none).
  const std::string& grammar_text() const { return grammar_text_; }
  /// @returns the name the inline grammar text goes by in errors.
  const std::string& grammar_source() const { return grammar_source_; }

  /// The grammar of another agent (by name): its changes are verified against it when they arrive
  /// (without one, against this agent's own grammar).
  struct PeerGrammar {
    std::string agent, text, source;
  };
  /// Adds the grammar `text` (named `source`) of agent `agent`. Used only with a grammar of this
  /// agent's own; set it in the constructor. Host's thread.
  void add_peer_grammar(std::string agent, std::string text, std::string source) {
    peer_grammars_.push_back({std::move(agent), std::move(text), std::move(source)});
  }
  /// @returns the peer grammars, in the order added.
  const std::vector<PeerGrammar>& peer_grammars() const { return peer_grammars_; }

  using Subscriber = std::function<void(AgentContext&, const graph::ChangeBatch&)>;
  /// Calls `fn` with the part of every change batch (local or merged) that `filter` selects.
  /// `fn` runs on the host's thread at the next pump. Host's thread.
  /// @pre Called in the constructor or setup(), not from a subscription's own callback.
  void subscribe(ChangeFilter filter, Subscriber fn) { subscriptions_.push_back({std::move(filter), std::move(fn)}); }
  /// Adds an action; the runtime evaluates actions in the order they were added. `interest`
  /// narrows which changes make the runtime search for it again (timers and ticks always do).
  /// Host's thread.
  /// @pre Called in the constructor or setup() (the engine sizes its tables when setup() returns);
  ///      `a` is not null.
  void add_action(std::unique_ptr<Action> a, ChangeFilter interest = {}) {
    actions_.push_back({std::move(a), std::move(interest)});
  }

  // ---- calls from other threads ----

  /// Thread-safe: runs `fn` on the agent's thread (its host's) at the host's next tick (about
  /// 10 ms), where it may read and write the graph.
  /// Tasks wait until the host has started the agent; they do not wake a sleeping host (use the
  /// host's own post() for that: Engine::post(), DdsReplica::post()).
  void post(std::function<void()> fn) {
    std::lock_guard<std::mutex> lock(posted_mu_);
    posted_.push_back(std::move(fn));
  }
  /// Thread-safe: as post(), and returns a future of `fn`'s result (or of its exception). An agent
  /// whose host stops before the task ran leaves the future with std::future_error
  /// (broken_promise). @pre not waited on from the agent's own thread.
  /// @returns the future of fn()'s result.
  template <class F>
  auto call(F fn) -> std::future<std::invoke_result_t<F&>> {
    return posted_call([this](std::function<void()> task) { post(std::move(task)); }, std::move(fn));
  }
  /// The host's side: takes the tasks posted so far (the runtime runs them in tick()).
  /// @returns them in post order, leaving none. Thread-safe.
  std::vector<std::function<void()>> take_posted() {
    std::vector<std::function<void()>> out;
    std::lock_guard<std::mutex> lock(posted_mu_);
    out.swap(posted_);
    return out;
  }

  struct Subscription {
    ChangeFilter filter;
    Subscriber fn;
  };
  struct ActionEntry {
    std::unique_ptr<Action> action;
    ChangeFilter interest;
  };
  /// The host's side. @returns the subscriptions, in the order added. Host's thread only.
  std::vector<Subscription>& subscriptions() { return subscriptions_; }
  /// The host's side. @returns the actions, in the order added. Host's thread only.
  std::vector<ActionEntry>& actions() { return actions_; }

 private:
  std::string name_;
  std::string grammar_file_, grammar_text_, grammar_source_;
  std::vector<PeerGrammar> peer_grammars_;
  std::vector<Subscription> subscriptions_;
  std::vector<ActionEntry> actions_;
  std::mutex posted_mu_;
  std::vector<std::function<void()>> posted_;  // guarded by posted_mu_
};

}  // namespace quiver::agents
