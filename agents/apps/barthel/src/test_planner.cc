// The Planner agent: the Barthel test conducted by writing each step into the graph, replanned on silence,
// misunderstanding or the person lost, and continued from the graph by a restarted Planner.
#include "quiver/agents/apps/barthel/test_planner.h"

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/apps/barthel/items.h"

namespace quiver::agents::inline apps::barthel {

using graph::NodeId;
using graph::Symbol;
using graph::Value;
using nlohmann::json;

namespace {

const std::vector<BarthelItem>& items() { return barthel_items(); }

std::vector<std::string> labels(const BarthelItem& item) {
  std::vector<std::string> out;
  for (const auto& o : item.options) out.push_back(o.label);
  return out;
}

std::string spoken_list(const std::vector<std::string>& options) {
  std::string s;
  for (std::size_t i = 0; i < options.size(); ++i) {
    if (i) s += i + 1 == options.size() ? ", or " : ", ";
    s += options[i];
  }
  return s;
}

json answers_of(const graph::Graph& g, NodeId test) {
  json a = json::parse(attr_string(g, test, "answers", "{}"), nullptr, false);
  return a.is_object() ? a : json::object();
}

bool final_status(const std::string& s) { return s == "done" || s == "clinician_called"; }

// One step of the test: the changes go into one transaction.
struct Step {
  graph::Graph& g;
  graph::Transaction tx;
  NodeId test;
  std::int64_t seq;

  Step(graph::Graph& graph, NodeId t) : g(graph), tx(graph.begin()), test(t), seq(attr_int(graph, t, "seq", 0)) {}

  Status set(std::string_view attr, Value v) { return tx.set(test, attr, std::move(v)); }

  // test -[say]-> u: the next thing to say (and to show).
  Result<std::int64_t> say(const std::string& purpose, const std::string& text, int item = -1, int attempt = 0,
                           const std::string& title = {}, const std::string& screen_text = {},
                           const std::vector<std::string>& options = {}, bool buttons = false) {
    const std::int64_t s = ++seq;
    std::string name = "u" + std::to_string(s);
    if (g.find_node(name)) name += "_" + g.replica().to_string();
    std::vector<std::pair<Symbol, Value>> attrs = {
        {Symbol("seq"), Value(s)},         {Symbol("text"), Value(text)},
        {Symbol("purpose"), Value(purpose)}, {Symbol("item"), Value(static_cast<std::int64_t>(item))},
        {Symbol("attempt"), Value(static_cast<std::int64_t>(attempt))}};
    if (!title.empty()) attrs.emplace_back(Symbol("title"), Value(title));
    if (!screen_text.empty()) attrs.emplace_back(Symbol("screen_text"), Value(screen_text));
    if (!options.empty()) attrs.emplace_back(Symbol("options"), Value(join_lines(options)));
    if (buttons) attrs.emplace_back(Symbol("buttons"), Value(true));
    auto u = tx.create_node("utterance", name, std::move(attrs));
    if (!u.ok()) return u.error();
    if (Status st = tx.insert_edge(test, *u, edge::kSay); !st.ok()) return st.error();
    if (Status st = tx.set(test, "seq", Value(s)); !st.ok()) return st.error();
    return s;
  }

  // Unspoken prompts of `purpose` will not be said any more.
  Status obsolete(const std::string& purpose) {
    for (const Prompt& p : prompts(g))
      if (p.purpose == purpose && !marked(g, node::kSpeaker, edge::kSpoke, p.id) && !attr_bool(g, p.id, "obsolete"))
        if (Status s = tx.set(p.id, "obsolete", Value(true)); !s.ok()) return s;
    return {};
  }

  Status commit() {
    auto c = tx.commit();
    return c.ok() ? Status{} : Status(c.error());
  }
};

}  // namespace

namespace {

// The result the answers so far make (items in the standard order; unanswered ones without score).
devices::TestResult result_of(const json& answers, std::string patient, std::string status, std::int64_t now_ns) {
  devices::TestResult r;
  r.patient = std::move(patient);
  r.status = std::move(status);
  for (const auto& it : items()) {
    if (!answers.contains(it.id)) continue;
    const json& x = answers[it.id];
    devices::ItemResult ir{it.id, std::nullopt, x.value("answer", ""), x.value("channel", "")};
    if (x.contains("score")) ir.score = x["score"].get<int>();
    if (ir.score) r.total += *ir.score;
    r.items.push_back(ir);
  }
  r.finished_ns = now_ns;
  return r;
}

}  // namespace

devices::TestResult result_from_graph(const graph::Graph& g, std::int64_t now_ns) {
  NodeId test = node_id(g, node::kTest);
  return result_of(answers_of(g, test), attr_string(g, test, "patient", "patient"),
                   attr_string(g, test, "status", "waiting"), now_ns);
}

class Planner::Conduct final : public Action {
 public:
  explicit Conduct(Planner& p) : Action("conduct"), p_(p) {}

  std::vector<Match> find(AgentContext& ctx) override {
    NodeId t = node_id(ctx.graph(), node::kTest);
    if (t.is_null() || final_status(attr_string(ctx.graph(), t, "status", "waiting"))) return {};
    Match m;
    m.key = "test";
    m.nodes["test"] = t;
    return {m};
  }

  bool holds(AgentContext& ctx, const Match& m) override {
    return !final_status(attr_string(ctx.graph(), m.at("test"), "status", "waiting"));
  }

  std::optional<LockNeed> lock(AgentContext&, const Match& m) override {
    return LockNeed{m.at("test"), p_.opt_.lock_priority};
  }

  Status start(AgentContext& ctx, const Match& m) override {
    graph::Transaction tx = ctx.graph().begin();
    if (Status s = tx.set(m.at("test"), "planner", Value(ctx.name())); !s.ok()) return s;
    auto c = tx.commit();
    if (!c.ok()) return c.error();
    ctx.log("conducts the test from item " + std::to_string(attr_int(ctx.graph(), m.at("test"), "item", 0)) +
            " (" + attr_string(ctx.graph(), m.at("test"), "status", "waiting") + ")");
    return {};
  }

  Progress process(AgentContext& ctx, const Match& m) override {
    Status s = step(ctx, m.at("test"));
    if (!s.ok()) {
      ctx.log("step refused: " + s.error().to_string());
      return Progress::kRunning;  // try again on the next tick
    }
    return final_status(attr_string(ctx.graph(), m.at("test"), "status")) ? Progress::kDone : Progress::kRunning;
  }

  Status finish(AgentContext&, const Match&) override { return {}; }
  void cancel(AgentContext& ctx, const Match&, CancelReason why) override {
    ctx.log(std::string("stops conducting (") + to_string(why) + "); the graph holds where the test is");
  }

 private:
  Status step(AgentContext& ctx, NodeId test) {
    graph::Graph& g = ctx.graph();
    const std::int64_t now = ctx.now();
    const std::string status = attr_string(g, test, "status", "waiting");
    const bool present = person_present(g);
    const bool absent = attr_bool(g, test, "absent");
    const std::string phase = attr_string(g, test, "phase");
    ++p_.steps_;

    if (status == "waiting") {
      p_.state_ = "waiting for the patient";
      if (!present) return {};
      Step st(g, test);
      auto u = st.say("intro",
                      "Hello. I am going to ask you about ten activities of daily living. You can answer by "
                      "voice, or by touching the screen when I show the options.",
                      -1, 0, "Barthel index", "Ten questions about daily activities");
      if (!u.ok()) return u.error();
      for (auto [k, v] : {std::pair<const char*, Value>{"status", Value("running")}, {"phase", Value("intro")},
                          {"item", Value(std::int64_t{0})}, {"attempt", Value(std::int64_t{0})},
                          {"current", Value(*u)}, {"unanswered", Value(std::int64_t{0})}})
        if (Status s = st.set(k, v); !s.ok()) return s;
      ctx.log("the patient is here: the test starts");
      return st.commit();
    }
    if (status != "running") return {};

    // The person lost: ask them to sit down; the deadlines stop.
    if (!present && !absent) {
      Step st(g, test);
      if (Status s = st.set("absent", Value(true)); !s.ok()) return s;
      if (Status s = st.obsolete("welcome_back"); !s.ok()) return s;
      auto u = st.say("call_back", "Please sit down in front of me again. We will continue when you are back.");
      if (!u.ok()) return u.error();
      ctx.log("the person was lost during item " + std::to_string(attr_int(g, test, "item")) + " (" + phase +
              "): asks them to come back");
      return st.commit();
    }
    if (present && absent) {
      Step st(g, test);
      if (Status s = st.set("absent", Value(false)); !s.ok()) return s;
      if (Status s = st.obsolete("call_back"); !s.ok()) return s;
      if (phase == "listening") {
        auto u = st.say("welcome_back", "Welcome back. Please answer when you are ready.");
        if (!u.ok()) return u.error();
        if (Status s = st.set("deadline_ns", Value(now + p_.opt_.answer_timeout_ns)); !s.ok()) return s;
        if (Status s = st.set("suspended", Value(false)); !s.ok()) return s;
      }
      ctx.log("the person is back: item " + std::to_string(attr_int(g, test, "item")) + " resumes");
      return st.commit();
    }
    if (!present) {
      p_.state_ = "waiting for the patient to come back";
      return {};
    }

    const auto cur = prompt_by_seq(g, attr_int(g, test, "current", -1));
    const int item = static_cast<int>(attr_int(g, test, "item", 0));
    const int attempt = static_cast<int>(attr_int(g, test, "attempt", 0));
    const bool spoken = cur && marked(g, node::kSpeaker, edge::kSpoke, cur->id);

    if (phase == "intro") {
      p_.state_ = "introducing the test";
      if (!spoken) return {};
      Step st(g, test);
      if (Status s = ask(st, 0, 1, ""); !s.ok()) return s;
      return st.commit();
    }
    if (phase == "asking") {
      p_.state_ = "asking item " + std::to_string(item);
      if (!spoken) return {};
      Step st(g, test);
      if (Status s = st.set("phase", Value("listening")); !s.ok()) return s;
      if (Status s = st.set("deadline_ns", Value(now + p_.opt_.answer_timeout_ns)); !s.ok()) return s;
      if (Status s = st.set("suspended", Value(false)); !s.ok()) return s;
      return st.commit();
    }
    if (phase != "listening" || !cur) return {};
    p_.state_ = "listening for item " + std::to_string(item);

    if (auto a = answer_to(g, cur->id)) {
      Step st(g, test);
      if (a->option >= 0 && static_cast<std::size_t>(a->option) < items()[static_cast<std::size_t>(item)].options.size()) {
        const auto& opt = items()[static_cast<std::size_t>(item)].options[static_cast<std::size_t>(a->option)];
        json ans = answers_of(g, test);
        ans[items()[static_cast<std::size_t>(item)].id] = {
            {"option", a->option}, {"score", opt.score}, {"answer", opt.label}, {"channel", a->channel}};
        if (Status s = st.set("answers", Value(ans.dump())); !s.ok()) return s;
        ctx.log("item " + std::to_string(item) + ": \"" + opt.label + "\" (" + a->channel + "), " +
                std::to_string(opt.score) + " points");
        if (Status s = next(ctx, st, item, ans); !s.ok()) return s;
      } else if (attempt == 1) {
        if (Status s = ask(st, item, 2, "Sorry, I did not understand. "); !s.ok()) return s;
      } else {
        if (Status s = unanswered(ctx, st, item); !s.ok()) return s;
      }
      return st.commit();
    }

    // The deadline runs only while every agent the answer depends on is heard.
    bool healthy = true;
    for (const std::string& n : p_.opt_.needs) healthy = healthy && ctx.hears(n);
    const bool suspended = attr_bool(g, test, "suspended");
    const std::int64_t deadline = attr_int(g, test, "deadline_ns", now);
    if (!healthy) {
      if (suspended) return {};
      Step st(g, test);
      if (Status s = st.set("suspended", Value(true)); !s.ok()) return s;
      if (Status s = st.set("remaining_ns", Value(std::max<std::int64_t>(deadline - now, 0))); !s.ok()) return s;
      ctx.log("an agent the answer needs is silent: the deadline stands still");
      return st.commit();
    }
    if (suspended) {
      Step st(g, test);
      const std::int64_t remaining = std::max<std::int64_t>(attr_int(g, test, "remaining_ns", 0), 2'000'000'000);
      if (Status s = st.set("suspended", Value(false)); !s.ok()) return s;
      if (Status s = st.set("deadline_ns", Value(now + remaining)); !s.ok()) return s;
      return st.commit();
    }
    if (now < deadline) return {};
    Step st(g, test);
    if (attempt == 1) {
      if (Status s = ask(st, item, 2, ""); !s.ok()) return s;
    } else {
      if (Status s = unanswered(ctx, st, item); !s.ok()) return s;
    }
    return st.commit();
  }

  // Introduce the item and ask (attempt 1), or repeat its options by voice and on the screen (2).
  Status ask(Step& st, int item, int attempt, const std::string& prefix) {
    const auto& it = items()[static_cast<std::size_t>(item)];
    const auto opts = labels(it);
    Result<std::int64_t> u = attempt == 1
        ? st.say("question", it.name + ". " + it.question + " You can say: " + spoken_list(opts) + ".", item, 1,
                 it.name, it.question, opts, false)
        : st.say("retry", prefix + "Let me repeat the options for " + it.name + ": " + spoken_list(opts) +
                              ". Please say one, or touch it on the screen.",
                 item, 2, it.name, "Please choose one:", opts, true);
    if (!u.ok()) return u.error();
    for (auto [k, v] : {std::pair<const char*, Value>{"phase", Value("asking")},
                        {"item", Value(static_cast<std::int64_t>(item))},
                        {"attempt", Value(static_cast<std::int64_t>(attempt))}, {"current", Value(*u)}})
      if (Status s = st.set(k, v); !s.ok()) return s;
    return {};
  }

  Status next(AgentContext& ctx, Step& st, int item, const json& answers) {
    if (static_cast<std::size_t>(item) + 1 < items().size()) return ask(st, item + 1, 1, "");
    // Every item asked: store the result, say goodbye.
    devices::TestResult r =
        result_of(answers, attr_string(st.g, st.test, "patient", "patient"), "completed", ctx.now());
    if (Status s = p_.store_.store(r); !s.ok()) return s;
    auto u = st.say("goodbye", "The test is finished. Your score is " + std::to_string(r.total) +
                                   " out of 100. Thank you very much.");
    if (!u.ok()) return u.error();
    ctx.log("the test is complete: " + std::to_string(r.total) + " of 100; result stored");
    for (auto [k, v] : {std::pair<const char*, Value>{"phase", Value("closing")}, {"status", Value("done")},
                        {"total", Value(static_cast<std::int64_t>(r.total))}, {"current", Value(*u)}})
      if (Status s = st.set(k, v); !s.ok()) return s;
    return {};
  }

  Status unanswered(AgentContext& ctx, Step& st, int item) {
    json ans = answers_of(st.g, st.test);
    ans[items()[static_cast<std::size_t>(item)].id] = {{"unanswered", true}};
    if (Status s = st.set("answers", Value(ans.dump())); !s.ok()) return s;
    const std::int64_t n = attr_int(st.g, st.test, "unanswered", 0) + 1;
    if (Status s = st.set("unanswered", Value(n)); !s.ok()) return s;
    ctx.log("item " + std::to_string(item) + " unanswered (" + std::to_string(n) + ")");
    if (n < 2) return next(ctx, st, item, ans);
    // Two unanswered items: page the clinician, store what we have.
    devices::TestResult r =
        result_of(ans, attr_string(st.g, st.test, "patient", "patient"), "clinician_called", ctx.now());
    if (Status s = p_.pager_.page("Barthel test of " + r.patient + ": two items unanswered (last: " +
                                      items()[static_cast<std::size_t>(item)].name + "); please come.",
                                  ctx.now());
        !s.ok())
      return s;
    if (Status s = p_.store_.store(r); !s.ok()) return s;
    NodeId clinician = node_id(st.g, node::kClinician);
    if (Status s = st.tx.insert_edge(st.test, clinician, edge::kCalls); !s.ok()) return s;
    auto u = st.say("clinician", "I have called a clinician, who will come to help us. Thank you.");
    if (!u.ok()) return u.error();
    ctx.log("two items unanswered: the clinician is paged; result stored");
    for (auto [k, v] : {std::pair<const char*, Value>{"phase", Value("closing")}, {"status", Value("clinician_called")},
                        {"total", Value(static_cast<std::int64_t>(r.total))}, {"current", Value(*u)}})
      if (Status s = st.set(k, v); !s.ok()) return s;
    return {};
  }

  Planner& p_;
};

Planner::Planner(devices::ResultStore& store, devices::Pager& pager, PlannerOptions o, std::string name)
    : Agent(std::move(name)), store_(store), pager_(pager), opt_(std::move(o)) {
  set_grammar_text(std::string(role_grammar("planner")), "planner.aggl");
}

Planner::Planner(std::unique_ptr<devices::ResultStore> store, std::unique_ptr<devices::Pager> pager, PlannerOptions o,
                 std::string name)
    : Planner(*store, *pager, std::move(o), std::move(name)) {
  owned_store_ = std::move(store);
  owned_pager_ = std::move(pager);
}

Planner::~Planner() = default;

void Planner::setup(AgentContext&) {
  // Deadlines and health are time-driven: the runtime searches on every tick anyway.
  add_action(std::make_unique<Conduct>(*this));
}

void Planner::status(nlohmann::json& out) const {
  out["steps"] = steps_;
  out["state"] = state_;
}

}  // namespace quiver::agents::inline apps::barthel
