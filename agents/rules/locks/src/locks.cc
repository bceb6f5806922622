// Per-subgraph priority locks replicated in the graph: claims on a scope's root, one winner every replica agrees
// on, held once acknowledged, and writes into a scope locked by another refused.
#include "quiver/agents/rules/locks/locks.h"

#include <algorithm>

namespace quiver::agents::inline rules {

using graph::NodeId;
using graph::Symbol;
using graph::TxnOp;

namespace {

const Symbol& lock_attr() {
  static const Symbol s("__lock");
  return s;
}

graph::Value encode_claim(const LockClaim& c) {
  return graph::Value(graph::UInt64Vec{c.epoch, static_cast<std::uint64_t>(c.priority), c.holder.agent,
                                       c.holder.incarnation, static_cast<std::uint64_t>(c.lease_ns), c.free ? 1u : 0u});
}

std::optional<LockClaim> decode_claim(const graph::Value& v) {
  const auto* x = v.get_if<graph::UInt64Vec>();
  if (x == nullptr || x->size() != 6) return std::nullopt;
  LockClaim c;
  c.epoch = (*x)[0];
  c.priority = static_cast<std::int64_t>((*x)[1]);
  c.holder = PeerId{(*x)[2], (*x)[3]};
  c.lease_ns = static_cast<std::int64_t>((*x)[4]);
  c.free = (*x)[5] != 0;
  return c;
}

// The deterministic order of competing claims.
bool claim_less(const LockClaim& a, const LockClaim& b) {
  if (a.epoch != b.epoch) return a.epoch < b.epoch;
  if (a.priority != b.priority) return a.priority < b.priority;
  return a.holder < b.holder;
}

bool same_claim(const LockClaim& a, const LockClaim& b) {
  return a.epoch == b.epoch && a.holder == b.holder && a.free == b.free && a.priority == b.priority;
}

}  // namespace

const char* to_string(LockEventKind k) {
  switch (k) {
    case LockEventKind::kAcquired: return "acquired";
    case LockEventKind::kLost: return "lost";
    case LockEventKind::kReleased: return "released";
    case LockEventKind::kExpired: return "expired";
  }
  return "unknown";
}

LockManager::LockManager(graph::Graph& g, Replicator* replicator, std::function<std::int64_t()> now,
                         LockOptions options)
    : g_(g), rep_(replicator), now_(std::move(now)), opt_(options) {
  sub_ = g_.subscribe([this](const graph::ChangeBatch& b) { on_changes(b); });
}

LockManager::~LockManager() { g_.unsubscribe(sub_); }

bool LockManager::live(const PeerId& p) const {
  if (p == g_.replica()) return true;
  return rep_ == nullptr || rep_->member_alive(p);
}

bool LockManager::expired(const Seen& s) const {
  if (s.winner.free || s.winner.holder == g_.replica()) return false;
  // A claim lives while this replica hears its holder: the holder's engine is alive (its
  // heartbeats go on even while its code blocks), so a claim needs no renewal writes. A holder not
  // heard (it left, crashed, a partition cut it off, or it is an incarnation that is gone) no
  // longer holds.
  return !live(s.winner.holder);
}

void LockManager::emit(NodeId root, LockEventKind k, const LockClaim& c, std::string reason, std::int64_t latency) {
  if (cb_) cb_(LockEvent{root, k, c, std::move(reason), latency});
}

void LockManager::refresh(NodeId root) {
  auto values = g_.attr_values(root, lock_attr());
  if (values.empty()) {
    seen_.erase(root);
    mine_.erase(root);
    scopes_dirty_ = true;
    return;
  }
  Seen& s = seen_[root];
  LockClaim old = s.winner;
  s.max_epoch = 0;
  const graph::AttrValue* wv = nullptr;
  LockClaim w;
  for (const auto& v : values)
    if (auto c = decode_claim(v.value)) {
      s.max_epoch = std::max(s.max_epoch, c->epoch);
      if (wv == nullptr || claim_less(w, *c)) {
        wv = &v;
        w = *c;
      }
    }
  if (wv == nullptr) return;  // no claim decodes
  // A new write of the winning claim (a new claim) restarts the clock.
  if (!(wv->dot == s.winner_dot)) {
    s.winner_dot = wv->dot;
    s.changed_at = now_();
    s.expiry_reported = false;
  }
  s.winner = w;
  if (!same_claim(old, w)) {
    scopes_dirty_ = true;
    // Someone else claims: acknowledge at once so that the claimant need not wait a heartbeat.
    if (rep_ && !(w.holder == g_.replica())) rep_->announce_soon();
  }
  auto mine = mine_.find(root);
  if (mine != mine_.end() && !(w.holder == g_.replica() && w.epoch == mine->second.epoch && !w.free)) {
    std::string reason;
    if (w.free) reason = "released by " + g_.origin_name(w.holder);
    else if (w.epoch == mine->second.epoch) reason = "resolved in favour of a concurrent claim (after a partition or a race)";
    else if (w.priority > mine->second.priority) reason = "preempted by priority " + std::to_string(w.priority);
    else reason = "superseded by epoch " + std::to_string(w.epoch);
    mine_.erase(mine);
    scopes_dirty_ = true;
    emit(root, LockEventKind::kLost, w, reason);
  }
}

void LockManager::on_changes(const graph::ChangeBatch& b) {
  for (const auto& n : b.nodes) {
    if (n.kind == graph::ChangeKind::kDeleted) {
      if (seen_.erase(n.id) + mine_.erase(n.id) > 0) scopes_dirty_ = true;
      continue;
    }
    for (Symbol a : n.attrs)
      if (a == lock_attr()) refresh(n.id);
    if (n.kind == graph::ChangeKind::kCreated && g_.attr(n.id, lock_attr())) refresh(n.id);
  }
  for (const auto& e : b.edges)
    if (e.key.type == graph::symbols::rt() && e.kind != graph::ChangeKind::kUpdated) scopes_dirty_ = true;
}

std::optional<LockClaim> LockManager::winner(NodeId root) const {
  auto it = seen_.find(root);
  if (it == seen_.end() || it->second.winner.free || expired(it->second)) return std::nullopt;
  return it->second.winner;
}

std::vector<std::pair<NodeId, LockClaim>> LockManager::winners() const {
  std::vector<std::pair<NodeId, LockClaim>> out;
  for (const auto& [root, seen] : seen_)
    if (auto w = winner(root)) out.emplace_back(root, *w);
  return out;
}

bool LockManager::pending(NodeId root) const {
  auto m = mine_.find(root);
  return m != mine_.end() && !holds(root);
}

bool LockManager::holds(NodeId root) const {
  auto m = mine_.find(root);
  if (m == mine_.end()) return false;
  auto w = winner(root);
  if (!w || !(w->holder == g_.replica()) || w->epoch != m->second.epoch) return false;
  if (rep_ == nullptr) return true;
  // Acknowledged by every peer we hear from: none can hold a competing claim unseen by us.
  if (!rep_->all_peers_hold(g_.replica(), m->second.seq)) return false;
  // A takeover also waits, once, until nothing the live peers hold is missing here.
  if (m->second.takeover && !m->second.caught_up)
    m->second.caught_up = rep_->live_peer_count() == 0 || rep_->synced();
  return !m->second.takeover || m->second.caught_up;
}

Status LockManager::write_claim(NodeId root, const LockClaim& c) {
  // Library code never commits inside a caller's transaction.
  if (g_.transaction_open())
    return make_error(ErrorCode::kRefused, "a transaction is open on this graph: claim or release locks before begin() "
                                           "or after commit(), never inside a transaction");
  auto tx = g_.begin();
  Status s = tx.set(root, lock_attr(), encode_claim(c));
  if (!s.ok()) return s;
  auto r = tx.commit();
  if (!r.ok()) return r.error();
  return {};
}

Status LockManager::acquire(NodeId root, std::int64_t priority) {
  if (!g_.has_node(root)) return make_error(ErrorCode::kNotFound, "acquire(): node " + root.to_string() + " does not exist");
  if (g_.transaction_open())
    return make_error(ErrorCode::kRefused, "acquire(): a transaction is open on this graph; acquire locks before begin() "
                                           "or after commit(), never inside a transaction");
  refresh(root);
  std::uint64_t max_epoch = 0;
  bool takeover = false;
  if (auto it = seen_.find(root); it != seen_.end()) {
    max_epoch = it->second.max_epoch;
    takeover = expired(it->second);  // the winner is another holder's claim, its holder not heard
  }
  if (auto w = winner(root)) {
    if (w->holder == g_.replica() && mine_.count(root)) return {};  // already ours
    if (!(w->holder == g_.replica()) && w->priority >= priority)
      return make_error(ErrorCode::kRefused, "acquire(): '" + g_.name_of(root) + "' is locked by " +
                                                 g_.origin_name(w->holder) + " with priority " + std::to_string(w->priority) +
                                                 " (asked " + std::to_string(priority) + ")");
  }
  LockClaim c{max_epoch + 1, priority, g_.replica(), opt_.lease_ns, false};
  mine_[root] = Mine{c.epoch, 0, priority, now_(), false, takeover};
  Status s = write_claim(root, c);
  if (!s.ok()) {
    mine_.erase(root);
    return s;
  }
  mine_[root].seq = rep_ ? rep_->last_seq() : 0;
  // Gossip membership acknowledges only on demand: ask the peers that have not.
  if (rep_) rep_->want_acks(mine_[root].seq);
  scopes_dirty_ = true;
  return {};
}

Status LockManager::release(NodeId root) {
  auto m = mine_.find(root);
  if (m == mine_.end()) return make_error(ErrorCode::kNotFound, "release(): no claim on " + root.to_string());
  if (g_.transaction_open())
    return make_error(ErrorCode::kRefused, "release(): a transaction is open on this graph; release locks before "
                                           "begin() or after commit(), never inside a transaction");
  std::uint64_t max_epoch = m->second.epoch;
  if (auto it = seen_.find(root); it != seen_.end())
    max_epoch = std::max(max_epoch, it->second.max_epoch);
  LockClaim c{max_epoch + 1, 0, g_.replica(), 0, true};
  mine_.erase(m);
  scopes_dirty_ = true;
  Status s = write_claim(root, c);
  emit(root, LockEventKind::kReleased, c, "released");
  return s;
}

Status LockManager::acquire_all(std::vector<NodeId> roots, std::int64_t priority) {
  std::sort(roots.begin(), roots.end());
  std::vector<NodeId> done;
  for (NodeId r : roots) {
    Status s = acquire(r, priority);
    if (!s.ok()) {
      for (NodeId d : done) (void)release(d);
      return s;
    }
    done.push_back(r);
  }
  return {};
}

void LockManager::tick() {
  const std::int64_t now = now_();
  // Acquired / lost transitions of our claims (refresh() reports losses seen in merges).
  for (auto it = mine_.begin(); it != mine_.end();) {
    NodeId root = it->first;
    bool now_held = holds(root);
    if (now_held && !it->second.held) {
      it->second.held = true;
      emit(root, LockEventKind::kAcquired, seen_[root].winner, "acknowledged by every live peer",
           now - it->second.requested_at);
    } else if (!now_held && it->second.held) {
      it->second.held = false;  // suspended: a peer reappeared that has not acknowledged us yet
    }
    ++it;
  }
  for (auto& [root, s] : seen_) {
    if (s.winner.free || s.winner.holder == g_.replica() || s.expiry_reported) continue;
    if (expired(s)) {
      s.expiry_reported = true;
      scopes_dirty_ = true;
      emit(root, LockEventKind::kExpired, s.winner,
           "the holder left");
    }
  }
  if (scopes_dirty_) rebuild_scopes();
}

void LockManager::rebuild_scopes() const {
  scopes_dirty_ = false;
  foreign_.clear();
  own_.clear();
  for (const auto& [root, s] : seen_) {
    if (s.winner.free || expired(s) || !g_.has_node(root)) continue;
    const bool ours = s.winner.holder == g_.replica();
    std::vector<NodeId> stack{root};
    while (!stack.empty()) {
      NodeId n = stack.back();
      stack.pop_back();
      if (ours) own_[n] = std::max(own_[n], s.winner.epoch);
      else foreign_.emplace(n, root);
      for (NodeId c : g_.rt_children(n)) stack.push_back(c);
    }
  }
}

bool LockManager::locked_by_other(NodeId node) const {
  if (scopes_dirty_) rebuild_scopes();
  return foreign_.count(node) != 0;
}

std::uint64_t LockManager::fence(NodeId node) const {
  if (scopes_dirty_) rebuild_scopes();
  if (own_.empty()) return 0;
  auto it = own_.find(node);
  return it == own_.end() ? 0 : it->second;
}

Status LockManager::check(const graph::Graph& g, const std::vector<TxnOp>& ops) const {
  if (scopes_dirty_) rebuild_scopes();
  if (foreign_.empty()) return {};
  auto refuse = [&](NodeId n) {
    NodeId root = foreign_.at(n);
    const LockClaim& w = seen_.at(root).winner;
    return make_error(ErrorCode::kRefused, "'" + g.name_of(n) + "' is in the scope of '" + g.name_of(root) +
                                               "', locked by " + g.origin_name(w.holder) + " (priority " +
                                               std::to_string(w.priority) + ", epoch " + std::to_string(w.epoch) +
                                               "); only the holder may change it");
  };
  for (const TxnOp& op : ops) {
    if (op.kind == TxnOp::Kind::kCreateNode) continue;
    if ((op.kind == TxnOp::Kind::kSetAttr || op.kind == TxnOp::Kind::kRemoveAttr) && op.attr == lock_attr()) continue;
    if (foreign_.count(op.node)) return refuse(op.node);
    if (!op.other.is_null() && foreign_.count(op.other)) return refuse(op.other);
  }
  return {};
}

void LockManager::install(graph::Graph::CommitValidator then) {
  g_.set_commit_validator([this, then](const graph::Graph& g, const std::vector<TxnOp>& ops) -> Status {
    if (then) {
      Status s = then(g, ops);
      if (!s.ok()) return s;
    }
    return check(g, ops);
  });
  g_.set_fence_provider([this](NodeId n) { return fence(n); });
}

}  // namespace quiver::agents
