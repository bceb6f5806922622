#include "quiver/agents/runtime/engine/agent_runtime.h"

#include "quiver/base/hash.h"

#include <algorithm>

namespace quiver::agents::inline runtime {

AgentRuntime::AgentRuntime(Agent& agent, graph::Graph& g, Replicator* replicator, RuntimeOptions options)
    : agent_(agent), g_(g), rep_(replicator), opt_(std::move(options)), rng_(opt_.seed) {
  locks_ = std::make_unique<LockManager>(g_, rep_, opt_.clock, opt_.locks);
  locks_->on_event([this](const LockEvent& e) { on_lock_event(e); });
  sub_ = g_.subscribe([this](const graph::ChangeBatch& b) { inbox_.push_back(b); });
}

AgentRuntime::~AgentRuntime() {
  g_.unsubscribe(sub_);
  if (started_) g_.set_commit_validator(nullptr);
}

bool AgentRuntime::hears(std::string_view agent_name) const {
  if (!rep_) return false;
  for (const PeerInfo& p : rep_->peers())
    if (p.alive && !p.suspect && !p.observer && p.name == agent_name) return true;
  return false;
}

void AgentRuntime::log(std::string_view line) {
  if (opt_.log) opt_.log(line);
}

Status AgentRuntime::start() {
  Result<Grammar> grammar = make_error(ErrorCode::kNotFound, "");
  if (!agent_.grammar_text().empty()) grammar = parse_grammar(agent_.grammar_text(), agent_.grammar_source());
  else if (!agent_.grammar_file().empty()) grammar = load_grammar_file(agent_.grammar_file());
  if (!agent_.grammar_text().empty() || !agent_.grammar_file().empty()) {
    if (!grammar.ok()) return grammar.error();
    guard_ = std::make_unique<GrammarGuard>(g_, GrammarChecker(std::move(*grammar)), agent_.name());
    for (const Agent::PeerGrammar& pg : agent_.peer_grammars()) {
      auto pgram = parse_grammar(pg.text, pg.source);
      if (!pgram.ok()) return pgram.error();
      guard_->verify_with(fnv1a64(pg.agent), GrammarChecker(std::move(*pgram)));
    }
    guard_->on_unverified([this](const graph::ReplicaId& from, const Error& e) {
      log("unverified change from " + from.to_string() + ": " + e.message);
    });
  }
  locks_->install(guard_ ? guard_->validator() : graph::Graph::CommitValidator{});
  started_ = true;
  agent_.setup(*this);
  dirty_.assign(agent_.actions().size(), true);
  evaluate();
  return {};
}

bool AgentRuntime::interested(std::size_t action, const graph::ChangeBatch& b) const {
  const ChangeFilter& f = agent_.actions()[action].interest;
  if (f.node_types.empty() && f.edge_types.empty() && f.attributes.empty()) return true;
  return !f.select(b).empty();
}

void AgentRuntime::deliver() {
  // Batches committed by subscribers are delivered in the same call (bounded, against ping-pong).
  for (std::size_t round = 0; round < 16 && !inbox_.empty(); ++round) {
    std::vector<graph::ChangeBatch> batches;
    batches.swap(inbox_);
    for (const auto& b : batches) {
      for (std::size_t i = 0; i < dirty_.size(); ++i)
        if (!dirty_[i] && interested(i, b)) dirty_[i] = true;
      for (auto& s : agent_.subscriptions()) {
        graph::ChangeBatch part = s.filter.select(b);
        if (!part.empty()) s.fn(*this, part);
      }
    }
  }
}

void AgentRuntime::pump() {
  if (!started_) return;
  deliver();
  evaluate();
}

void AgentRuntime::tick() {
  if (!started_) return;
  // Calls from other threads (Agent::post / Agent::call), in the order they came.
  for (auto& fn : agent_.take_posted()) fn();
  pump();
  const std::int64_t t = now();
  while (!timers_.empty() && timers_.top().due <= t) {
    Timer tm = timers_.top();
    timers_.pop();
    auto it = timer_fns_.find(tm.id);
    if (it == timer_fns_.end()) continue;  // cancelled
    std::function<void()> fn = it->second;
    if (tm.period > 0) {
      tm.due += tm.period;
      if (tm.due <= t) tm.due = t + tm.period;  // a host that fell behind does not replay ticks
      timers_.push(tm);
    } else {
      timer_fns_.erase(it);
    }
    fn();
  }
  locks_->tick();
  if (guard_) guard_->tick();
  // Process what runs; then search everything again (time itself may call for an action).
  for (std::size_t i = 0; i < runs_.size();) {
    Run& r = runs_[i];
    if (!r.started) {
      ++i;
      continue;
    }
    Action& a = *agent_.actions()[r.action].action;
    Progress p = a.process(*this, r.match);
    if (p == Progress::kRunning) {
      ++i;
      continue;
    }
    end_run(i, p == Progress::kDone ? std::nullopt : std::optional<CancelReason>(CancelReason::kFailed));
  }
  std::fill(dirty_.begin(), dirty_.end(), true);
  pump();
  agent_.on_tick(*this);
  pump();
}

void AgentRuntime::stop() {
  if (!started_) return;
  while (!runs_.empty()) end_run(runs_.size() - 1, CancelReason::kStopping);
  agent_.teardown(*this);
  pump();
}

std::vector<AgentRuntime::RunView> AgentRuntime::runs() const {
  std::vector<RunView> out;
  for (const Run& r : runs_) out.push_back(RunView{agent_.actions()[r.action].action->name(), r.match.key, r.started});
  return out;
}

TimerId AgentRuntime::after(std::int64_t delay_ns, std::function<void()> fn) {
  const TimerId id = next_timer_++;
  timer_fns_.emplace(id, std::move(fn));
  timers_.push(Timer{now() + std::max<std::int64_t>(0, delay_ns), id, 0});
  return id;
}

TimerId AgentRuntime::every(std::int64_t period_ns, std::function<void()> fn) {
  const TimerId id = next_timer_++;
  timer_fns_.emplace(id, std::move(fn));
  const std::int64_t p = std::max<std::int64_t>(1, period_ns);
  timers_.push(Timer{now() + p, id, p});
  return id;
}

void AgentRuntime::cancel(TimerId id) { timer_fns_.erase(id); }

void AgentRuntime::emit(ActionEvent::Kind k, const Run& r, CancelReason why) {
  if (event_cb_) event_cb_(ActionEvent{k, agent_.actions()[r.action].action->name(), r.match.key, now(), why});
}

void AgentRuntime::on_lock_event(const LockEvent& e) {
  if (e.kind != LockEventKind::kLost) return;
  // Cancel after the merge that revealed it is fully applied: the runs are ended in evaluate().
  for (std::size_t i = 0; i < runs_.size(); ++i)
    if (runs_[i].lock && runs_[i].lock->root == e.root) pending_cancels_.emplace_back(i, CancelReason::kLockLost);
  log("lock on '" + g_.name_of(e.root) + "' lost: " + e.reason);
}

// Ends run `index`: finished (nullopt) or cancelled for `why`; releases its lock.
void AgentRuntime::end_run(std::size_t index, std::optional<CancelReason> why) {
  Run r = std::move(runs_[index]);
  runs_.erase(runs_.begin() + static_cast<long>(index));
  for (auto& [i, reason] : pending_cancels_)
    if (i > index) --i;
    else if (i == index) i = SIZE_MAX;
  Action& a = *agent_.actions()[r.action].action;
  if (r.started) {
    if (!why) {
      Status s = a.finish(*this, r.match);
      if (!s.ok()) log(a.name() + " " + r.match.key + ": finish refused: " + s.error().to_string());
      ++stats_.finished;
      emit(ActionEvent::Kind::kFinished, r);
      done_.emplace(r.action, r.match.key);
    } else {
      a.cancel(*this, r.match, *why);
      ++stats_.cancelled;
      emit(ActionEvent::Kind::kCancelled, r, *why);
    }
  }
  // The lock goes when no other run of this agent needs the same scope.
  if (r.lock && std::none_of(runs_.begin(), runs_.end(), [&](const Run& o) { return o.lock && o.lock->root == r.lock->root; }))
    (void)locks_->release(r.lock->root);
  dirty_[r.action] = true;
}

void AgentRuntime::start_run(Run& r) {
  Action& a = *agent_.actions()[r.action].action;
  Status s = a.start(*this, r.match);
  if (!s.ok()) {
    ++stats_.refused_starts;
    log(a.name() + " " + r.match.key + ": start refused: " + s.error().to_string());
    retry_at_[{r.action, r.match.key}] = now() + opt_.retry_ns;
    return;
  }
  r.started = true;
  ++stats_.started;
  emit(ActionEvent::Kind::kStarted, r);
}

void AgentRuntime::evaluate() {
  if (evaluating_) return;  // an action's own commit asked for it: the loop below sees it
  evaluating_ = true;
  for (int round = 0; round < 8; ++round) {
    evaluate_once();
    if (inbox_.empty() && pending_cancels_.empty()) break;
    deliver();  // what the actions committed, before looking again
  }
  evaluating_ = false;
}

void AgentRuntime::evaluate_once() {
  // 1. Lock losses reported by the lock manager.
  auto cancels = std::move(pending_cancels_);
  pending_cancels_.clear();
  std::sort(cancels.begin(), cancels.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [i, why] : cancels)
    if (i < runs_.size()) end_run(i, why);
  // 2. Running (or waiting) actions whose precondition no longer holds.
  for (std::size_t i = runs_.size(); i-- > 0;) {
    Run& r = runs_[i];
    Action& a = *agent_.actions()[r.action].action;
    if (!a.holds(*this, r.match)) end_run(i, CancelReason::kPreconditionGone);
  }
  // 3. Waiting for a lock: start once it is held.
  for (Run& r : runs_)
    if (!r.started && r.lock && locks_->holds(r.lock->root)) {
      auto retry = retry_at_.find({r.action, r.match.key});
      if (retry != retry_at_.end() && now() < retry->second) continue;
      start_run(r);
    }
  // 4. Search for changes: what calls for each action now.
  for (std::size_t ai = 0; ai < agent_.actions().size(); ++ai) {
    if (!dirty_[ai]) continue;
    dirty_[ai] = false;
    Action& a = *agent_.actions()[ai].action;
    std::vector<Match> found = a.find(*this);
    // Keys no longer found may run again later; keys still found and done stay done.
    for (auto it = done_.lower_bound({ai, std::string()}); it != done_.end() && it->first == ai;) {
      bool still = std::any_of(found.begin(), found.end(), [&](const Match& m) { return m.key == it->second; });
      it = still ? std::next(it) : done_.erase(it);
    }
    for (Match& m : found) {
      if (done_.count({ai, m.key})) continue;
      bool running = std::any_of(runs_.begin(), runs_.end(),
                                 [&](const Run& r) { return r.action == ai && r.match.key == m.key; });
      if (running) continue;
      auto retry = retry_at_.find({ai, m.key});
      if (retry != retry_at_.end()) {
        if (now() < retry->second) continue;
        retry_at_.erase(retry);
      }
      Run r;
      r.action = ai;
      r.match = std::move(m);
      r.lock = a.lock(*this, r.match);
      if (r.lock) {
        if (!locks_->holds(r.lock->root)) {
          Status s = locks_->acquire(r.lock->root, r.lock->priority);
          if (!s.ok()) continue;  // someone with a higher priority holds it: search again later
        }
        runs_.push_back(std::move(r));
        emit(ActionEvent::Kind::kWaitingLock, runs_.back());
        if (locks_->holds(runs_.back().lock->root)) start_run(runs_.back());
      } else {
        runs_.push_back(std::move(r));
        start_run(runs_.back());
      }
      if (!runs_.back().started && !runs_.back().lock) runs_.pop_back();  // start refused: retry later
    }
  }
}

}  // namespace quiver::agents
