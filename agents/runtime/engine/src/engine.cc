// The agent engine: the one loop of a replica and its agent, whatever hosts them.
#include "quiver/agents/runtime/engine/engine.h"

#include <algorithm>

#include "quiver/agents/runtime/engine/action_loop.h"
#include "quiver/base/hash.h"

namespace quiver::agents::inline runtime {

Engine::Engine(graph::Graph& g, Replicator* replicator, EngineOptions options)
    : g_(g),
      rep_(replicator),
      opt_(std::move(options)),
      rng_(opt_.seed),
      name_(replicator != nullptr ? replicator->options().name : std::string()),
      watch_(name_) {
  jobs_ = std::make_unique<JobRunner>(opt_.jobs, [this](std::function<void()> fn) { post(std::move(fn)); });
  jobs_->on_error([this](const std::string& line) { post([this, line] { log(line); }); });
  if (opt_.locks_enabled) make_locks();
}

Engine::Engine(Agent& agent, graph::Graph& g, Replicator* replicator, EngineOptions options)
    : Engine(g, replicator, std::move(options)) {
  attach(agent);
}

Engine::~Engine() {
  jobs_.reset();  // before the loop and the agent its completions would reach
  loop_.reset();
  if (started_) g_.set_commit_validator(nullptr);
}

void Engine::attach(Agent& agent) {
  agent_ = &agent;
  name_ = agent.name();
  watch_.set_agent(name_);
  make_locks();
  loop_ = std::make_unique<ActionLoop>(*this, agent, stats_);
  loop_->on_event([this](const ActionEvent& e) {
    if (event_cb_) event_cb_(e);
  });
}

void Engine::make_locks() {
  if (locks_) return;
  locks_ = std::make_unique<LockManager>(g_, rep_, opt_.clock, opt_.locks);
  locks_->on_event([this](const LockEvent& e) {
    if (loop_) loop_->on_lock_event(e);
  });
}

const std::string& Engine::name() const { return name_; }

LockManager& Engine::locks() {
  make_locks();
  return *locks_;
}

bool Engine::hears(std::string_view agent_name) const {
  if (!rep_) return false;
  const std::uint64_t agent = fnv1a64(agent_name);  // an agent's id is the hash of its name
  for (const PeerInfo& p : rep_->peers())
    if (p.alive && !p.suspect && !p.observer && (p.name == agent_name || p.id.agent == agent)) return true;
  return false;
}

void Engine::log(std::string_view line) {
  if (opt_.log) opt_.log(line);
}

Status Engine::load_grammar() {
  std::string text, source, file;
  std::vector<Agent::PeerGrammar> peers;
  if (agent_ != nullptr && (!agent_->grammar_text().empty() || !agent_->grammar_file().empty())) {
    text = agent_->grammar_text();
    source = agent_->grammar_source();
    file = agent_->grammar_file();
    peers = agent_->peer_grammars();
  } else {
    text = opt_.grammar_text;
    source = opt_.grammar_source;
    file = opt_.grammar_file;
  }
  if (text.empty() && file.empty()) return {};
  Result<Grammar> grammar = !text.empty() ? parse_grammar(text, source) : load_grammar_file(file);
  if (!grammar.ok()) return grammar.error();
  guard_ = std::make_unique<GrammarGuard>(g_, GrammarChecker(std::move(*grammar)), name_);
  for (const Agent::PeerGrammar& pg : peers) {
    auto pgram = parse_grammar(pg.text, pg.source);
    if (!pgram.ok()) return pgram.error();
    guard_->verify_with(fnv1a64(pg.agent), GrammarChecker(std::move(*pgram)));
    peers_verified_.insert(fnv1a64(pg.agent));
  }
  guard_->on_unverified([this](const graph::ReplicaId& from, const Error& e) {
    const std::string line = "a change from " + g_.origin_name(from) + " (" + from.to_string() +
                             ") is not verified by its grammar" +
                             (peers_verified_.count(from.agent) ? "" : " (no grammar given for that agent: checked with this agent's own; add_peer_grammar())") +
                             ": " + e.message;
    if (opt_.warn) opt_.warn(line);
    else log(line);
  });
  return {};
}

void Engine::install_checks() {
  if (locks_) locks_->install(guard_ ? guard_->validator() : graph::Graph::CommitValidator{});
  else if (guard_) guard_->install();
}

Status Engine::start() {
  if (Status s = load_grammar(); !s.ok()) return s;
  install_checks();
  started_ = true;
  if (loop_) loop_->start();
  return {};
}

void Engine::stop() {
  if (started_ && loop_) loop_->stop();
}

void Engine::on_action_event(std::function<void(const ActionEvent&)> cb) { event_cb_ = std::move(cb); }

const Engine::Stats& Engine::stats() const { return stats_; }

std::vector<Engine::RunView> Engine::runs() const { return loop_ ? loop_->runs() : std::vector<RunView>{}; }

void Engine::on_sample(const Sample& s) {
  if (rep_ != nullptr) rep_->on_sample(s, now());
}

void Engine::pump() {
  if (started_ && loop_) loop_->pump();
}

bool Engine::within_budget() const { return now() - turn_start_ < opt_.turn_budget_ns; }

void Engine::step() {
  if (rep_ != nullptr) rep_->tick(now());
  tick();
  if (rep_ != nullptr) rep_->flush();
}

void Engine::run_posted() {
  turn_start_ = now();
  std::vector<std::function<void()>> tasks;
  {
    std::lock_guard<std::mutex> lock(posted_mu_);
    tasks.swap(posted_);
  }
  if (agent_ != nullptr && started_)
    for (auto& fn : agent_->take_posted()) tasks.push_back(std::move(fn));
  std::size_t ran = 0;
  for (; ran < tasks.size(); ++ran) {
    if (ran > 0 && !within_budget()) break;
    auto in = user_code("a posted task");
    tasks[ran]();
  }
  if (ran < tasks.size()) {
    // What is left runs at the next round, after the protocol's work in between.
    ++stats_.turns_over_budget;
    std::lock_guard<std::mutex> lock(posted_mu_);
    posted_.insert(posted_.begin(), std::make_move_iterator(tasks.begin() + static_cast<long>(ran)),
                   std::make_move_iterator(tasks.end()));
  }
}

void Engine::run_timers() {
  if (!started_ && loop_ != nullptr) return;  // an agent's timers start with it
  if (timers_.next_due() > now()) return;
  turn_start_ = now();
  timers_.run_due(now(), [&] {
    if (within_budget()) return true;
    ++stats_.turns_over_budget;
    return false;
  });
}

void Engine::tick() {
  run_posted();
  if (!started_ && loop_ != nullptr) return;  // an agent's timers and checks start with it
  pump();
  run_timers();
  if (locks_) locks_->tick();
  if (guard_) guard_->tick();
  if (!started_ || loop_ == nullptr) return;
  // Process what runs; then search everything again (time itself may call for an action).
  loop_->process();
  loop_->dirty_all();
  loop_->pump();
  loop_->on_tick();
  loop_->pump();
}

bool Engine::quiet() const { return !tasks_waiting() && (loop_ == nullptr || loop_->idle()); }

bool Engine::tasks_waiting() const {
  std::lock_guard<std::mutex> lock(posted_mu_);
  return !posted_.empty();
}

void Engine::post(std::function<void()> fn) {
  {
    std::lock_guard<std::mutex> lock(posted_mu_);
    posted_.push_back(std::move(fn));
  }
  if (wake_) wake_();
}

TimerId Engine::after(std::int64_t delay_ns, std::function<void()> fn) {
  return timers_.at(now() + std::max<std::int64_t>(0, delay_ns), [this, fn = std::move(fn)] {
    auto in = user_code("a timer");
    fn();
  });
}

TimerId Engine::every(std::int64_t period_ns, std::function<void()> fn) {
  const std::int64_t p = std::max<std::int64_t>(1, period_ns);
  return timers_.every(now() + p, p, [this, fn = std::move(fn)] {
    auto in = user_code("a timer");
    fn();
  });
}

void Engine::run_job(std::function<void()> work, std::function<void()> done) {
  jobs_->run(std::move(work), [this, done = std::move(done)] {
    if (!done) return;
    auto in = user_code("a job's completion");
    done();
  });
}

}  // namespace quiver::agents::inline runtime
