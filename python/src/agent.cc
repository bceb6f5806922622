// quiver.Agent: a replica on Cyclone DDS with its own thread. Python's threads hand it work with
// call() (post + wait, the GIL released while waiting); callbacks run on the agent's thread with
// the GIL held.

#include <chrono>
#include <cstdio>
#include <future>

#include "agent_core.h"
#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/graph/world_file.h"

namespace quiver::python {

// ---------------------------------------------------------------- AgentCore

Result<std::shared_ptr<AgentCore>> AgentCore::start(AgentOptions options) {
  std::shared_ptr<AgentCore> core(new AgentCore(std::move(options)));
  core->thread_ = std::thread([c = core.get()] { c->loop(); });
  std::unique_lock<std::mutex> lock(core->mu_);
  core->cv_.wait(lock, [&] { return core->started_; });
  if (core->start_error_) {
    Error e = *core->start_error_;
    lock.unlock();
    core->thread_.join();
    return e;
  }
  return core;
}

AgentCore::~AgentCore() {
  if (thread_.joinable()) {
    wake_to_stop();
    if (on_thread()) thread_.detach();  // the last reference went away inside a callback
    else thread_.join();
  }
}

void AgentCore::wake_to_stop() {
  stop_ = true;
  std::lock_guard<std::mutex> lock(mu_);
  if (replica_) replica_->stop();  // its round ends now, not at its next tick
}

void AgentCore::stop() {
  wake_to_stop();
  if (thread_.joinable() && !on_thread()) thread_.join();
}

bool AgentCore::post_quietly(std::function<void()> fn) {
  std::lock_guard<std::mutex> lock(mu_);
  if (!running_ || !replica_) return false;
  replica_->post(std::move(fn));
  return true;
}

void AgentCore::loop() {
  thread_id_ = std::this_thread::get_id();
  auto fail = [this](Error e) {
    std::lock_guard<std::mutex> lock(mu_);
    start_error_ = std::move(e);
    started_ = true;
    cv_.notify_all();
  };
  // The engine holds the locks and the grammar guard, and installs their checks.
  opt_.replica.engine.locks_enabled = opt_.locks;
  opt_.replica.engine.locks = opt_.lock_options;
  opt_.replica.engine.grammar_file = opt_.grammar_file;
  opt_.replica.engine.grammar_text = opt_.grammar_text;
  auto created = agents::DdsReplica::create(opt_.replica);
  if (!created.ok()) return fail(created.error());
  std::unique_ptr<agents::DdsReplica> replica = std::move(*created);
  graph::Graph& g = replica->graph();
  if (Status s = replica->engine().start(); !s.ok()) return fail(s.error());
  if (opt_.hang_ns > 0)
    replica->keep_alive(opt_.hang_ns, [](const std::string& line) {
      std::fprintf(stderr, "quiver: warning: %s\n", line.c_str());
    }, [](const std::string& line) { std::fprintf(stderr, "quiver: %s\n", line.c_str()); });
  if (opt_.frames) frames_ = std::make_unique<kinematics::FrameTree>(g);
  {
    std::lock_guard<std::mutex> lock(mu_);
    replica_ = std::move(replica);
    running_ = true;
    started_ = true;
    cv_.notify_all();
  }
  // The replica's own ticks, timers and samples decide when a round ends; stop() wakes it.
  while (!stop_) replica_->spin_once(agents::DdsReplica::kSpinLook);
  if (opt_.hand_over_ns > 0) replica_->hand_over(opt_.hand_over_ns);
  std::unique_ptr<agents::DdsReplica> leaving;
  {
    std::lock_guard<std::mutex> lock(mu_);
    running_ = false;
    leaving = std::move(replica_);
  }
  // Python callbacks go with these (their holders take the GIL to let go).
  frames_.reset();
  leaving.reset();
}

void AgentCore::keep_error(py::error_already_set& e) {
  if (first_error_ == nullptr) first_error_ = py::object(e.value()).release().ptr();
}

py::object AgentCore::take_error() {
  PyObject* e = first_error_;
  first_error_ = nullptr;
  return e ? py::reinterpret_steal<py::object>(e) : py::none();
}

// ---------------------------------------------------------------- ownership helpers

bool Owner::on_owner_thread() const {
  if (scope) return scope->thread == std::this_thread::get_id();
  return !agent || agent->on_thread();
}

void Owner::check(const char* fn) const {
  auto wrong_thread = [fn] {
    PyErr_SetString(py::module_::import("quiver").attr("WrongThreadError").ptr(),
                    (std::string(fn) + "(): an agent's graph is used on the agent's thread only: "
                                       "use Agent.call(fn) or a callback")
                        .c_str());
    throw py::error_already_set();
  };
  if (scope) {
    if (!scope->open) {
      raise(make_error(ErrorCode::kInvalidArgument,
                       std::string(fn) + "(): an agent's context and graph are valid only while run_agent() runs"));
    }
    if (scope->thread != std::this_thread::get_id()) wrong_thread();
    return;
  }
  if (!agent) return;
  if (!agent->running()) {
    raise(make_error(ErrorCode::kInvalidArgument, std::string(fn) + "(): the agent has stopped"));
  }
  if (!agent->on_thread()) wrong_thread();
}

PyCallback::~PyCallback() {
  if (Py_IsInitialized()) {
    py::gil_scoped_acquire gil;
    delete fn_;
  }
}

std::optional<agents::CallbackWatch::Scope> mark_user_code(const std::weak_ptr<AgentCore>& agent) {
  std::optional<agents::CallbackWatch::Scope> in;
  if (auto core = agent.lock(); core && core->running() && core->on_thread())
    in.emplace(core->replica().engine().user_code("a Python callback"));
  return in;
}

void report_callback_error(py::error_already_set& e, const std::weak_ptr<AgentCore>& agent) {
  if (auto core = agent.lock()) {
    core->keep_error(e);
    py::print("quiver: a callback raised", py::str(e.value()), py::arg("file") = py::module_::import("sys").attr("stderr"));
  } else {
    e.discard_as_unraisable("quiver callback");
  }
}

namespace {

std::mutex g_agents_mu;
std::vector<std::weak_ptr<AgentCore>> g_agents;

/// Runs `task` on the agent's thread with the GIL and waits for it (GIL released meanwhile);
/// re-raises what it raised. On the agent's thread, runs it at once.
void run_on(const std::shared_ptr<AgentCore>& core, const std::function<void()>& task) {
  if (core->on_thread()) return task();
  struct Outcome {
    PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
    std::string cpp_error;
  };
  auto promise = std::make_shared<std::promise<void>>();
  auto outcome = std::make_shared<Outcome>();
  std::future<void> done = promise->get_future();
  const std::function<void()>* t = &task;  // alive: this thread waits for the task
  bool posted = core->post_quietly([promise, outcome, t] {
    {
      py::gil_scoped_acquire gil;
      try {
        (*t)();
      } catch (py::error_already_set& e) {
        e.restore();
        PyErr_Fetch(&outcome->type, &outcome->value, &outcome->trace);
      } catch (const std::exception& e) {
        outcome->cpp_error = e.what();
      }
    }
    promise->set_value();
  });
  if (!posted) raise(make_error(ErrorCode::kInvalidArgument, "the agent has stopped"));
  bool broken = false;
  {
    py::gil_scoped_release release;
    try {
      done.get();
    } catch (const std::future_error&) {
      broken = true;  // the agent stopped before running it
    }
  }
  if (broken) raise(make_error(ErrorCode::kInvalidArgument, "the agent stopped before running the call"));
  if (outcome->type != nullptr) {
    PyErr_Restore(outcome->type, outcome->value, outcome->trace);
    throw py::error_already_set();
  }
  if (!outcome->cpp_error.empty()) throw std::runtime_error(outcome->cpp_error);
}

struct PyAgent {
  std::shared_ptr<AgentCore> core;
  GraphHandle graph;
  std::string name;

  template <class F>
  auto on_thread(F&& fn) {
    using R = decltype(fn());
    if constexpr (std::is_void_v<R>) {
      run_on(core, [&] { fn(); });
    } else {
      std::optional<R> r;
      run_on(core, [&] { r.emplace(fn()); });
      return std::move(*r);
    }
  }
  void stop() {
    if (core->on_thread()) {
      raise(make_error(ErrorCode::kInvalidArgument, "Agent.stop(): called on the agent's own thread (from a callback)"));
    }
    {
      py::gil_scoped_release release;
      core->stop();
    }
    check();
  }
  void check() {
    py::object e = core->take_error();
    if (!e.is_none()) {
      PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(e.ptr())), e.ptr());
      throw py::error_already_set();
    }
  }
  agents::LockManager& locks() {
    if (core->locks() == nullptr) raise(make_error(ErrorCode::kInvalidArgument, "this agent was started with locks=False"));
    return *core->locks();
  }
};

void stop_all_agents() {
  std::vector<std::shared_ptr<AgentCore>> live;
  {
    std::lock_guard<std::mutex> lock(g_agents_mu);
    for (auto& w : g_agents)
      if (auto c = w.lock()) live.push_back(std::move(c));
    g_agents.clear();
  }
  py::gil_scoped_release release;
  for (auto& c : live) c->stop();
}

}  // namespace

void bind_agent(py::module_& m) {
  py::class_<agents::LockClaim>(m, "LockClaim")
      .def_readonly("epoch", &agents::LockClaim::epoch)
      .def_readonly("priority", &agents::LockClaim::priority)
      .def_readonly("holder", &agents::LockClaim::holder)
      .def_readonly("free", &agents::LockClaim::free);

  py::class_<PyAgent>(m, "Agent",
                      "A replica of the world graph on Cyclone DDS, driven by its own thread (no executive: it "
                      "replicates with every agent of its DDS domain). The graph lives on that thread: run code on "
                      "it with call(fn) / write(fn), or in callbacks (subscribe(), on_lock_event(), "
                      "on_violation()), which run there with the GIL held.\n\n"
                      "Network safety: dds_config='loopback' (the default) binds 127.0.0.1 with multicast off.")
      .def(py::init([](const std::string& name, std::uint32_t domain, const std::string& dds_config,
                       std::optional<std::string> grammar, std::optional<std::string> grammar_text, bool locks,
                       double lock_lease, bool frames, bool observer, double lease, double hand_over,
                       double hang, std::optional<std::string> world, std::optional<std::string> world_text,
                       std::optional<std::string> schema) {
             AgentOptions o;
             if (schema) {
               auto s = agents::schema::Schema::load(*schema);
               if (!s.ok()) raise(make_error(s.error().code, "Agent(): schema: " + s.error().message));
               o.replica.schema = std::make_shared<const agents::schema::Schema>(std::move(*s));
             }
             // A seed depends only on the file: agents started together with it hold one world.
             std::optional<graph::WorldSeed> seed;
             if (world || world_text) {
               auto w = world ? graph::world_seed_file(*world) : graph::world_seed(*world_text, "world_text");
               if (!w.ok()) raise(make_error(w.error().code, "Agent(): world: " + w.error().message));
               seed = std::move(*w);
             }
             o.replica.name = name;
             o.replica.observer = observer;
             agents::ProcessFlags flags;
             flags.domain = domain;
             flags.dds_config = dds_config;
             check(flags.apply_to(o.replica.dds));
             o.replica.dds.lease_ns = static_cast<std::int64_t>(lease * 1e9);
             if (grammar) o.grammar_file = *grammar;
             if (grammar_text) o.grammar_text = *grammar_text;
             o.locks = locks;
             o.lock_options.lease_ns = static_cast<std::int64_t>(lock_lease * 1e9);
             o.frames = frames;
             if (!(hand_over >= 0 && hand_over <= 60))
               raise(make_error(ErrorCode::kInvalidArgument, "Agent(): hand_over must be 0..60 seconds"));
             o.hand_over_ns = static_cast<std::int64_t>(hand_over * 1e9);
             if (!(hang >= 0 && hang <= 3600))
               raise(make_error(ErrorCode::kInvalidArgument, "Agent(): hang must be 0..3600 seconds"));
             o.hang_ns = static_cast<std::int64_t>(hang * 1e9);
             Result<std::shared_ptr<AgentCore>> started = make_error(ErrorCode::kInternal, "");
             {
               py::gil_scoped_release release;
               started = AgentCore::start(std::move(o));
             }
             auto core = unwrap(std::move(started));
             {
               std::lock_guard<std::mutex> lock(g_agents_mu);
               g_agents.push_back(core);
             }
             PyAgent a;
             a.core = core;
             a.name = name;
             a.graph.owner.agent = core;
             // The graph is created by the time start() returns; it dies with the core's replica.
             graph::Graph* gp = nullptr;
             run_on(core, [&] {
               gp = &core->replica().graph();
               if (seed) (void)core->replica().replicator().seed(seed->delta);
             });
             a.graph.graph = std::shared_ptr<graph::Graph>(core, gp);
             return a;
           }),
           py::arg("name"), py::kw_only(), py::arg("domain") = 0, py::arg("dds_config") = "loopback",
           py::arg("grammar") = py::none(), py::arg("grammar_text") = py::none(), py::arg("locks") = true,
           py::arg("lock_lease") = 2.0, py::arg("frames") = true, py::arg("observer") = false,
           py::arg("lease") = 1.0, py::arg("hand_over") = 2.0, py::arg("hang") = 1.0,
           py::arg("world") = py::none(), py::arg("world_text") = py::none(), py::arg("schema") = py::none(),
           "Starts an agent named `name` (its id derives from it) on DDS domain `domain`. `grammar` (a file) "
           "or `grammar_text` makes every local transaction follow that grammar; `locks` enables priority "
           "locks; `frames` keeps a frame tree for RT lookups (frames()). On stop() the agent keeps "
           "replicating up to `hand_over` seconds until every live agent peer holds all it holds. A callback "
           "that blocks keeps the agent alive for its peers (its heartbeats go on); one running longer than "
           "`hang` seconds (0: never) is reported on stderr. `world` (a Quiver world file) or `world_text` seeds the "
           "shared graph (idempotent: agents started with the same file hold it once); `schema` is the shared "
           "vocabulary file every agent of the domain loads (docs/schema.md).")
      .def_readonly("name", &PyAgent::name)
      .def_property_readonly("id", [](PyAgent& a) { return a.on_thread([&]() -> graph::ReplicaId { return a.core->replica().id(); }); })
      .def_property_readonly("graph", [](PyAgent& a) { return a.graph; },
                             "The agent's graph: usable on the agent's thread only (in call() or callbacks).")
      .def_property_readonly("running", [](PyAgent& a) { return a.core->running(); })
      .def("call", [](PyAgent& a, py::function fn, py::args args) {
             py::object result;
             a.on_thread([&] { result = fn(py::cast(a.graph), *args); });
             return result;
           }, py::arg("fn"), "Runs fn(graph, *args) on the agent's thread and returns its result (or raises what it raised).")
      .def("write", [](PyAgent& a, py::function fn, py::args args) {
             py::object info;
             a.on_thread([&] {
               py::object txn = py::cast(a.graph).attr("transaction")();
               try {
                 fn(txn, *args);
               } catch (...) {
                 txn.attr("abort")();
                 throw;
               }
               info = txn.attr("commit")();
             });
             return info;
           }, py::arg("fn"), "Runs fn(transaction, *args) on the agent's thread and commits; returns the CommitInfo.")
      .def("subscribe", [](PyAgent& a, py::function cb, const std::vector<std::string>& node_types,
                           const std::vector<std::string>& edge_types, const std::vector<std::string>& attributes) {
             return a.on_thread([&] {
               return a.graph.get("subscribe").subscribe(to_filter(node_types, edge_types, attributes),
                                                         make_callback<graph::ChangeBatch>(cb, a.graph.owner));
             });
           }, py::arg("callback"), py::kw_only(), py::arg("node_types") = std::vector<std::string>{},
           py::arg("edge_types") = std::vector<std::string>{}, py::arg("attributes") = std::vector<std::string>{},
           "Calls callback(ChangeBatch) on the agent's thread after every change, with the part the filter "
           "selects (as Graph.subscribe). Returns an id.")
      .def("unsubscribe", [](PyAgent& a, std::uint64_t id) { a.on_thread([&] { a.graph.get("unsubscribe").unsubscribe(id); }); },
           py::arg("id"))
      .def("live_peer_count", [](PyAgent& a) { return a.on_thread([&] { return a.core->replica().replicator().live_peer_count(); }); })
      .def("peers", [](PyAgent& a) {
             return a.on_thread([&] {
               std::vector<std::string> out;
               for (const auto& p : a.core->replica().replicator().peers())
                 if (p.alive) out.push_back(p.name);
               return out;
             });
           }, "Names of the live peers.")
      .def("synced", [](PyAgent& a) { return a.on_thread([&] { return a.core->replica().replicator().synced(); }); },
           "True when this replica holds everything every live peer says it holds.")
      .def("digest", [](PyAgent& a) { return a.on_thread([&] { return a.core->replica().graph().digest().hex(); }); })
      .def("wait_until", [](PyAgent& a, py::function pred, double timeout, double poll) {
             auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
             while (true) {
               bool ok = false;
               a.on_thread([&] { ok = py::bool_(pred(py::cast(a.graph))); });
               if (ok) return true;
               if (std::chrono::steady_clock::now() >= deadline) return false;
               py::gil_scoped_release release;
               std::this_thread::sleep_for(std::chrono::duration<double>(poll));
             }
           }, py::arg("predicate"), py::arg("timeout") = 10.0, py::arg("poll") = 0.01,
           "Evaluates predicate(graph) on the agent's thread every `poll` seconds until it is true (returns True) "
           "or `timeout` passes (returns False).")
      .def("acquire", [](PyAgent& a, py::handle node, std::int64_t priority) {
             a.on_thread([&] { check(a.locks().acquire(to_node(a.graph.get("acquire"), node), priority)); });
           }, py::arg("root"), py::arg("priority"),
           "Claims the scope under `root` (RefusedError if a live claim of equal or higher priority holds it). "
           "It is held once acknowledged by every live peer (holds()).")
      .def("release", [](PyAgent& a, py::handle node) {
             a.on_thread([&] { check(a.locks().release(to_node(a.graph.get("release"), node))); });
           }, py::arg("root"))
      .def("holds", [](PyAgent& a, py::handle node) {
             return a.on_thread([&] { return a.locks().holds(to_node(a.graph.get("holds"), node)); });
           }, py::arg("root"))
      .def("pending", [](PyAgent& a, py::handle node) {
             return a.on_thread([&] { return a.locks().pending(to_node(a.graph.get("pending"), node)); });
           }, py::arg("root"))
      .def("lock_winner", [](PyAgent& a, py::handle node) {
             return a.on_thread([&] { return a.locks().winner(to_node(a.graph.get("lock_winner"), node)); });
           }, py::arg("root"))
      .def("locked_by_other", [](PyAgent& a, py::handle node) {
             return a.on_thread([&] { return a.locks().locked_by_other(to_node(a.graph.get("locked_by_other"), node)); });
           }, py::arg("node"))
      .def("on_lock_event", [](PyAgent& a, py::function cb) {
             a.on_thread([&] {
               auto fn = make_callback<py::object>(cb, a.graph.owner);
               a.locks().on_event([fn](const agents::LockEvent& e) {
                 py::gil_scoped_acquire gil;
                 py::dict d;
                 d["root"] = e.root;
                 d["kind"] = std::string(agents::to_string(e.kind));
                 d["claim"] = e.claim;
                 d["reason"] = e.reason;
                 d["latency_ns"] = e.latency_ns;
                 fn(d);
               });
             });
           }, py::arg("callback"),
           "callback(event: dict with root, kind ('acquired', 'lost', 'released', 'expired'), claim, reason, latency_ns).")
      .def("on_violation", [](PyAgent& a, py::function cb) {
             a.on_thread([&] {
               if (!a.core->guard()) raise(make_error(ErrorCode::kInvalidArgument, "on_violation(): this agent has no grammar"));
               auto fn = make_callback<py::object>(cb, a.graph.owner);
               a.core->guard()->on_violation([fn](const agents::Violation& v) {
                 py::gil_scoped_acquire gil;
                 py::dict binding;
                 for (const auto& [var, id] : v.binding) binding[py::str(var)] = id;
                 fn(py::make_tuple(v.constraint, binding));
               });
             });
           }, py::arg("callback"), "callback((constraint, {variable: NodeId})) when a merge produced a forbidden pattern.")
      .def("frames", [](PyAgent& a) {
             return a.on_thread([&] {
               if (!a.core->frames()) raise(make_error(ErrorCode::kInvalidArgument, "frames(): this agent was started with frames=False"));
               return std::make_unique<kinematics::FrameReader>(a.core->frames()->reader());
             });
           }, "A FrameReader for the calling thread: lock-free RT lookups (4x4 arrays) that never wait for the agent.")
      .def("check", &PyAgent::check, "Raises the first exception a callback raised (once).")
      .def("stop", &PyAgent::stop,
           "Hands over (up to `hand_over` s), leaves the domain (peers see it go at once) and stops the thread; "
           "then check().")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyAgent& a, py::handle, py::handle, py::handle) {
             a.stop();
             return false;
           });

  py::module_::import("atexit").attr("register")(py::cpp_function([] { stop_all_agents(); }));
}

}  // namespace quiver::python
