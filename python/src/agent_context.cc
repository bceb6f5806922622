// quiver.AgentContext: what a runtime agent's callbacks see of their host (its graph, time,
// timers, locks, random source, log). Valid while run_agent() runs, on its thread.

#include "agent_run.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/runtime/process/process_host.h"

namespace quiver::python {
namespace {

thread_local AgentRun* t_run = nullptr;

struct PyContext {
  agents::AgentContext* ctx = nullptr;
  GraphHandle graph;  ///< scoped to the run
  agents::AgentContext& get(const char* fn) const {
    graph.owner.check(fn);
    return *ctx;
  }
};

std::int64_t to_ns(double seconds, const char* fn) {
  if (!(seconds >= 0))
    raise(make_error(ErrorCode::kInvalidArgument,
                     std::string(fn) + "(): negative time " + std::to_string(seconds)));
  return static_cast<std::int64_t>(seconds * 1e9);
}

std::function<void()> timer_callback(py::function fn) {
  auto holder = std::make_shared<PyCallback>(std::move(fn));
  return [holder] { guarded([&] { holder->fn()(); }); };
}

// What a job's work returned or raised, handed from the worker thread to done() on the agent's
// thread; its Python objects are let go with the GIL held.
struct JobOutcome {
  py::object* result = nullptr;
  std::optional<py::error_already_set>* error = nullptr;
  ~JobOutcome() {
    if (!Py_IsInitialized()) return;
    py::gil_scoped_acquire gil;
    delete result;
    delete error;
  }
};

}  // namespace

AgentRun* current_run() { return t_run; }

void bind_current_run(AgentRun* r) { t_run = r; }

py::object context_object(agents::AgentContext& ctx) {
  AgentRun* run = t_run;
  if (run == nullptr) throw std::logic_error("quiver: an agent callback outside run_agent()");
  if (run->raw != &ctx || !run->ctx) {
    PyContext c;
    c.ctx = &ctx;
    c.graph.graph =
        std::shared_ptr<graph::Graph>(std::shared_ptr<void>(), &ctx.graph());  // not owned
    c.graph.owner.scope = run->scope;
    run->raw = &ctx;
    run->ctx = py::cast(std::move(c));
  }
  return run->ctx;
}

void keep_run_error(py::error_already_set& e) {
  AgentRun* run = t_run;
  if (run == nullptr || run->error) {
    e.discard_as_unraisable("quiver agent callback");
    return;
  }
  py::print("quiver: an agent callback raised", py::repr(e.value()),
            py::arg("file") = py::module_::import("sys").attr("stderr"));
  run->error.emplace(std::move(e));
  agents::request_stop();
}

bool run_failed() { return t_run != nullptr && t_run->error.has_value(); }

graph::ChangeFilter to_filter(const std::vector<std::string>& node_types,
                              const std::vector<std::string>& edge_types,
                              const std::vector<std::string>& attributes) {
  graph::ChangeFilter f;
  f.node_types = node_types;
  f.edge_types = edge_types;
  f.attributes = attributes;
  return f;
}

void bind_agent_context(py::module_& m) {
  py::class_<PyContext>(
      m, "AgentContext",
      "What a runtime agent's callbacks see of their host: its graph, the time, timers, its "
      "priority locks, its seeded random source and its log. Valid while run_agent() runs, on "
      "its thread (inside callbacks).")
      .def_property_readonly("name", [](const PyContext& c) { return c.get("name").name(); })
      .def_property_readonly(
          "graph",
          [](const PyContext& c) {
            c.get("graph");
            return c.graph;
          },
          "The agent's replica (valid during the run only).")
      .def(
          "now", [](const PyContext& c) { return c.get("now").now(); },
          "Now in nanoseconds (monotonic in a process, virtual in the simulator).")
      .def(
          "log", [](const PyContext& c, const std::string& line) { c.get("log").log(line); },
          py::arg("line"), "A line for the agent's log (stderr, named and timed by the host).")
      .def(
          "hears",
          [](const PyContext& c, const std::string& agent) { return c.get("hears").hears(agent); },
          py::arg("agent"), "True while a live agent of that name is heard.")
      .def(
          "random", [](const PyContext& c) { return c.get("random").rng().uniform(); },
          "Uniform in [0, 1) from the agent's one seeded random source.")
      .def(
          "randint",
          [](const PyContext& c, std::int64_t lo, std::int64_t hi) {
            if (hi < lo)
              raise(make_error(ErrorCode::kInvalidArgument, "randint(): hi " + std::to_string(hi) +
                                                                " < lo " + std::to_string(lo)));
            return c.get("randint").rng().range(lo, hi);
          },
          py::arg("lo"), py::arg("hi"),
          "Uniform in [lo, hi] from the agent's seeded random source.")
      .def(
          "after",
          [](const PyContext& c, double delay, py::function fn) {
            return c.get("after").after(to_ns(delay, "after"), timer_callback(std::move(fn)));
          },
          py::arg("delay"), py::arg("fn"),
          "Calls fn() once, `delay` seconds from now. Returns the timer's id.")
      .def(
          "every",
          [](const PyContext& c, double period, py::function fn) {
            if (!(period > 0))
              raise(make_error(ErrorCode::kInvalidArgument,
                               "every(): the period must be > 0, not " + std::to_string(period)));
            return c.get("every").every(to_ns(period, "every"), timer_callback(std::move(fn)));
          },
          py::arg("period"), py::arg("fn"),
          "Calls fn() every `period` seconds (the first time one period from now). Returns the "
          "timer's id.")
      .def(
          "cancel", [](const PyContext& c, agents::TimerId id) { c.get("cancel").cancel(id); },
          py::arg("timer"), "Cancels a timer (nothing if it already ran).")
      .def(
          "run_job",
          [](const PyContext& c, py::function work, std::optional<py::function> done) {
            auto w = std::make_shared<PyCallback>(std::move(work));
            auto d = done ? std::make_shared<PyCallback>(std::move(*done)) : nullptr;
            auto outcome = std::make_shared<JobOutcome>();
            c.get("run_job").run_job(
                [w, outcome] {
                  py::gil_scoped_acquire gil;
                  try {
                    outcome->result = new py::object(w->fn()());
                  } catch (py::error_already_set& e) {
                    outcome->error = new std::optional<py::error_already_set>(std::move(e));
                  }
                },
                [d, outcome] {
                  guarded([&] {
                    if (outcome->error != nullptr && outcome->error->has_value()) {
                      py::error_already_set e = std::move(**outcome->error);
                      outcome->error->reset();
                      throw e;
                    }
                    if (d) d->fn()(outcome->result != nullptr ? *outcome->result : py::none());
                  });
                });
          },
          py::arg("work"), py::arg("done") = py::none(),
          "Long work off the agent's thread: calls work() on a worker thread (it must not touch the "
          "graph or this context; the agent's loop goes on meanwhile), then done(result) on the agent's "
          "thread, where it may. Jobs of one agent run one at a time, in order. What work() raises is "
          "raised on the agent's thread, as a callback's would be.")
      .def(
          "acquire",
          [](const PyContext& c, py::handle root, std::int64_t priority) {
            auto& ctx = c.get("acquire");
            check(ctx.locks().acquire(to_node(ctx.graph(), root), priority));
          },
          py::arg("root"), py::arg("priority"),
          "Claims the scope under `root` (RefusedError if a live claim of equal or higher priority "
          "holds it).")
      .def(
          "release",
          [](const PyContext& c, py::handle root) {
            auto& ctx = c.get("release");
            check(ctx.locks().release(to_node(ctx.graph(), root)));
          },
          py::arg("root"))
      .def(
          "holds",
          [](const PyContext& c, py::handle root) {
            auto& ctx = c.get("holds");
            return ctx.locks().holds(to_node(ctx.graph(), root));
          },
          py::arg("root"),
          "True once this agent's claim on `root` is acknowledged by every live peer.")
      .def(
          "locked_by_other",
          [](const PyContext& c, py::handle node) {
            auto& ctx = c.get("locked_by_other");
            return ctx.locks().locked_by_other(to_node(ctx.graph(), node));
          },
          py::arg("node"), "True when another agent's claim covers `node`.");
}

}  // namespace quiver::python
