// The DSR loop of one agent: deliver changes, search, lock, start, process, finish or cancel.
#include "quiver/agents/runtime/engine/action_loop.h"

#include <algorithm>

namespace quiver::agents::inline runtime {

ActionLoop::ActionLoop(Engine& engine, Agent& agent, Engine::Stats& stats)
    : e_(engine), agent_(agent), stats_(stats) {
  sub_ = e_.graph().subscribe([this](const graph::ChangeBatch& b) { inbox_.push_back(b); });
}

ActionLoop::~ActionLoop() { e_.graph().unsubscribe(sub_); }

CallbackWatch::Scope ActionLoop::user(const char* callback, std::size_t action) {
  return e_.user_code(callback, &agent_.actions()[action].action->name());
}

void ActionLoop::start() {
  started_ = true;
  {
    auto in = e_.user_code("setup()");
    agent_.setup(e_);
  }
  dirty_.assign(agent_.actions().size(), true);
  evaluate();
}

bool ActionLoop::interested(std::size_t action, const graph::ChangeBatch& b) const {
  const ChangeFilter& f = agent_.actions()[action].interest;
  if (f.node_types.empty() && f.edge_types.empty() && f.attributes.empty()) return true;
  return !f.select(b).empty();
}

void ActionLoop::deliver() {
  // Batches committed by subscribers are delivered in the same call (bounded, against ping-pong).
  for (std::size_t round = 0; round < 16 && !inbox_.empty(); ++round) {
    std::vector<graph::ChangeBatch> batches;
    batches.swap(inbox_);
    for (const auto& b : batches) {
      for (std::size_t i = 0; i < dirty_.size(); ++i)
        if (!dirty_[i] && interested(i, b)) dirty_[i] = true;
      for (auto& s : agent_.subscriptions()) {
        graph::ChangeBatch part = s.filter.select(b);
        if (part.empty()) continue;
        auto in = e_.user_code("a subscription");
        s.fn(e_, part);
      }
    }
  }
}

void ActionLoop::pump() {
  if (!started_) return;
  deliver();
  evaluate();
}

void ActionLoop::process() {
  for (std::size_t i = 0; i < runs_.size();) {
    Run& r = runs_[i];
    if (!r.started) {
      ++i;
      continue;
    }
    Action& a = *agent_.actions()[r.action].action;
    Progress p;
    {
      auto in = user("process()", r.action);
      p = a.process(e_, r.match);
    }
    if (p == Progress::kRunning) {
      ++i;
      continue;
    }
    end_run(i, p == Progress::kDone ? std::nullopt : std::optional<CancelReason>(CancelReason::kFailed));
  }
}

void ActionLoop::dirty_all() { std::fill(dirty_.begin(), dirty_.end(), true); }

void ActionLoop::on_tick() {
  auto in = e_.user_code("on_tick()");
  agent_.on_tick(e_);
}

void ActionLoop::stop() {
  if (!started_) return;
  while (!runs_.empty()) end_run(runs_.size() - 1, CancelReason::kStopping);
  {
    auto in = e_.user_code("teardown()");
    agent_.teardown(e_);
  }
  pump();
}

std::vector<Engine::RunView> ActionLoop::runs() const {
  std::vector<Engine::RunView> out;
  for (const Run& r : runs_) out.push_back(Engine::RunView{agent_.actions()[r.action].action->name(), r.match.key, r.started});
  return out;
}

void ActionLoop::emit(ActionEvent::Kind k, const Run& r, CancelReason why) {
  if (event_cb_) event_cb_(ActionEvent{k, agent_.actions()[r.action].action->name(), r.match.key, e_.now(), why});
}

void ActionLoop::on_lock_event(const LockEvent& e) {
  if (e.kind != LockEventKind::kLost) return;
  // Cancel after the merge that revealed it is fully applied: the runs are ended in evaluate().
  for (std::size_t i = 0; i < runs_.size(); ++i)
    if (runs_[i].lock && runs_[i].lock->root == e.root) pending_cancels_.emplace_back(i, CancelReason::kLockLost);
  e_.log("lock on '" + e_.graph().name_of(e.root) + "' lost: " + e.reason);
}

// Ends run `index`: finished (nullopt) or cancelled for `why`; releases its lock.
void ActionLoop::end_run(std::size_t index, std::optional<CancelReason> why) {
  Run r = std::move(runs_[index]);
  runs_.erase(runs_.begin() + static_cast<long>(index));
  for (auto& [i, reason] : pending_cancels_)
    if (i > index) --i;
    else if (i == index) i = SIZE_MAX;
  Action& a = *agent_.actions()[r.action].action;
  if (r.started) {
    if (!why) {
      Status s;
      {
        auto in = user("finish()", r.action);
        s = a.finish(e_, r.match);
      }
      if (!s.ok()) e_.log(a.name() + " " + r.match.key + ": finish refused: " + s.error().to_string());
      ++stats_.finished;
      emit(ActionEvent::Kind::kFinished, r);
      done_.emplace(r.action, r.match.key);
    } else {
      {
        auto in = user("cancel()", r.action);
        a.cancel(e_, r.match, *why);
      }
      ++stats_.cancelled;
      emit(ActionEvent::Kind::kCancelled, r, *why);
    }
  }
  // The lock goes when no other run of this agent needs the same scope.
  if (r.lock && std::none_of(runs_.begin(), runs_.end(), [&](const Run& o) { return o.lock && o.lock->root == r.lock->root; }))
    (void)e_.locks().release(r.lock->root);
  dirty_[r.action] = true;
}

void ActionLoop::start_run(Run& r) {
  Action& a = *agent_.actions()[r.action].action;
  Status s;
  {
    auto in = user("start()", r.action);
    s = a.start(e_, r.match);
  }
  if (!s.ok()) {
    ++stats_.refused_starts;
    e_.log(a.name() + " " + r.match.key + ": start refused: " + s.error().to_string());
    retry_at_[{r.action, r.match.key}] = e_.now() + e_.retry_ns();
    return;
  }
  r.started = true;
  ++stats_.started;
  emit(ActionEvent::Kind::kStarted, r);
}

void ActionLoop::evaluate() {
  if (evaluating_) return;  // an action's own commit asked for it: the loop below sees it
  evaluating_ = true;
  for (int round = 0; round < 8; ++round) {
    evaluate_once();
    if (inbox_.empty() && pending_cancels_.empty()) break;
    deliver();  // what the actions committed, before looking again
  }
  evaluating_ = false;
}

void ActionLoop::evaluate_once() {
  LockManager& locks = e_.locks();
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
    bool holds;
    {
      auto in = user("holds()", r.action);
      holds = a.holds(e_, r.match);
    }
    if (!holds) end_run(i, CancelReason::kPreconditionGone);
  }
  // 3. Waiting for a lock: start once it is held.
  for (Run& r : runs_)
    if (!r.started && r.lock && locks.holds(r.lock->root)) {
      auto retry = retry_at_.find({r.action, r.match.key});
      if (retry != retry_at_.end() && e_.now() < retry->second) continue;
      start_run(r);
    }
  // 4. Search for changes: what calls for each action now.
  for (std::size_t ai = 0; ai < agent_.actions().size(); ++ai) {
    if (!dirty_[ai]) continue;
    dirty_[ai] = false;
    Action& a = *agent_.actions()[ai].action;
    std::vector<Match> found;
    {
      auto in = user("find()", ai);
      found = a.find(e_);
    }
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
        if (e_.now() < retry->second) continue;
        retry_at_.erase(retry);
      }
      Run r;
      r.action = ai;
      r.match = std::move(m);
      {
        auto in = user("lock()", ai);
        r.lock = a.lock(e_, r.match);
      }
      if (r.lock) {
        if (!locks.holds(r.lock->root)) {
          Status s = locks.acquire(r.lock->root, r.lock->priority);
          if (!s.ok()) continue;  // someone with a higher priority holds it: search again later
        }
        runs_.push_back(std::move(r));
        emit(ActionEvent::Kind::kWaitingLock, runs_.back());
        if (locks.holds(runs_.back().lock->root)) start_run(runs_.back());
      } else {
        runs_.push_back(std::move(r));
        start_run(runs_.back());
      }
      if (!runs_.back().started && !runs_.back().lock) runs_.pop_back();  // start refused: retry later
    }
  }
}

}  // namespace quiver::agents::inline runtime
