#pragma once
/// @file
/// Dot stores and causal CRDTs after Almeida, Shoker and Baquero, "Delta State Replicated Data
/// Types" (2018), section 7: DotSet, DotFun<V> and DotMap<K, S>, each joined under a causal
/// context; Causal<S> pairs a store with its context. A dot in the context but not in the store
/// means "seen and removed", so removals need no tombstones.
///
/// join(s, c, s', c') for a dot set: (s ∩ s') ∪ (s \ c') ∪ (s' \ c); dot functions likewise on
/// their keys; dot maps key by key, dropping keys whose store becomes empty.

#include <map>
#include <utility>
#include <vector>

#include "quiver/crdt/causal_context.h"
#include "quiver/crdt/dot.h"
#include "quiver/crdt/small_vector.h"

namespace quiver::crdt {

/// A value tagged with the dot of the event that wrote it, and an optional fencing epoch: an
/// application-level key consulted before the Lamport order when concurrent values compete
/// (a lock holder's epoch, so that a stale holder's concurrent write never wins).
template <class V>
struct Entry {
  Dot dot;
  V value;
  std::uint64_t fence = 0;
  friend bool operator==(const Entry&, const Entry&) = default;
};

/// Winner order among concurrent entries: fence first, then the dot's Lamport order.
template <class V>
bool entry_less(const Entry<V>& a, const Entry<V>& b) {
  if (a.fence != b.fence) return a.fence < b.fence;
  return lamport_less(a.dot, b.dot);
}

/// A set of dots. Usually one, so stored inline.
class DotSet {
 public:
  bool empty() const { return dots_.empty(); }
  std::size_t size() const { return dots_.size(); }
  bool contains(const Dot& d) const {
    for (const Dot& x : dots_)
      if (x == d) return true;
    return false;
  }
  void insert(const Dot& d) {
    if (!contains(d)) dots_.push_back(d);
  }
  bool erase(const Dot& d) {
    for (Dot* it = dots_.begin(); it != dots_.end(); ++it)
      if (*it == d) {
        dots_.swap_erase(it);
        return true;
      }
    return false;
  }
  const Dot* begin() const { return dots_.begin(); }
  const Dot* end() const { return dots_.end(); }
  template <class F>
  void for_each_dot(F&& f) const {
    for (const Dot& d : dots_) f(d);
  }

  static DotSet join(const DotSet& a, const CausalContext& ca, const DotSet& b, const CausalContext& cb) {
    DotSet out;
    for (const Dot& d : a.dots_)
      if (b.contains(d) || !cb.contains(d)) out.dots_.push_back(d);
    for (const Dot& d : b.dots_)
      if (!a.contains(d) && !ca.contains(d)) out.dots_.push_back(d);
    return out;
  }
  friend bool operator==(const DotSet& a, const DotSet& b) {
    if (a.size() != b.size()) return false;
    for (const Dot& d : a.dots_)
      if (!b.contains(d)) return false;
    return true;
  }

 private:
  SmallVec<Dot, 1> dots_;
};

/// A map from dots to values: the payload of a multi-value register.
template <class V>
class DotFun {
 public:
  using EntryT = Entry<V>;
  bool empty() const { return entries_.empty(); }
  std::size_t size() const { return entries_.size(); }
  const EntryT* begin() const { return entries_.begin(); }
  const EntryT* end() const { return entries_.end(); }
  EntryT* begin() { return entries_.begin(); }
  EntryT* end() { return entries_.end(); }
  const EntryT* find(const Dot& d) const {
    for (const EntryT& e : entries_)
      if (e.dot == d) return &e;
    return nullptr;
  }
  void insert(const Dot& d, V v, std::uint64_t fence = 0) {
    if (find(d) == nullptr) entries_.emplace_back(EntryT{d, std::move(v), fence});
  }
  bool erase(const Dot& d) {
    for (EntryT* it = entries_.begin(); it != entries_.end(); ++it)
      if (it->dot == d) {
        entries_.erase(it);
        return true;
      }
    return false;
  }
  void clear() { entries_.clear(); }
  template <class Pred>
  std::size_t erase_if(Pred pred) {
    return entries_.erase_if(pred);
  }
  template <class F>
  void for_each_dot(F&& f) const {
    for (const EntryT& e : entries_) f(e.dot);
  }

  static DotFun join(const DotFun& a, const CausalContext& ca, const DotFun& b, const CausalContext& cb) {
    DotFun out;
    for (const EntryT& e : a.entries_)
      if (b.find(e.dot) != nullptr || !cb.contains(e.dot)) out.entries_.push_back(e);
    for (const EntryT& e : b.entries_)
      if (a.find(e.dot) == nullptr && !ca.contains(e.dot)) out.entries_.push_back(e);
    return out;
  }
  friend bool operator==(const DotFun& a, const DotFun& b) {
    if (a.size() != b.size()) return false;
    for (const EntryT& e : a.entries_) {
      const EntryT* o = b.find(e.dot);
      if (o == nullptr || !(o->value == e.value) || o->fence != e.fence) return false;
    }
    return true;
  }

 private:
  SmallVec<EntryT, 1> entries_;
};

/// A map from keys to dot stores; keys whose store is empty are absent.
template <class K, class S>
class DotMap {
 public:
  bool empty() const { return map_.empty(); }
  std::size_t size() const { return map_.size(); }
  const S* find(const K& k) const {
    auto it = map_.find(k);
    return it == map_.end() ? nullptr : &it->second;
  }
  S& operator[](const K& k) { return map_[k]; }
  void erase(const K& k) { map_.erase(k); }
  auto begin() const { return map_.begin(); }
  auto end() const { return map_.end(); }
  template <class F>
  void for_each_dot(F&& f) const {
    for (const auto& [k, s] : map_) s.for_each_dot(f);
  }

  static DotMap join(const DotMap& a, const CausalContext& ca, const DotMap& b, const CausalContext& cb) {
    DotMap out;
    static const S kEmpty{};
    auto ia = a.map_.begin();
    auto ib = b.map_.begin();
    while (ia != a.map_.end() || ib != b.map_.end()) {
      if (ib == b.map_.end() || (ia != a.map_.end() && ia->first < ib->first)) {
        S s = S::join(ia->second, ca, kEmpty, cb);
        if (!s.empty()) out.map_.emplace_hint(out.map_.end(), ia->first, std::move(s));
        ++ia;
      } else if (ia == a.map_.end() || ib->first < ia->first) {
        S s = S::join(kEmpty, ca, ib->second, cb);
        if (!s.empty()) out.map_.emplace_hint(out.map_.end(), ib->first, std::move(s));
        ++ib;
      } else {
        S s = S::join(ia->second, ca, ib->second, cb);
        if (!s.empty()) out.map_.emplace_hint(out.map_.end(), ia->first, std::move(s));
        ++ia;
        ++ib;
      }
    }
    return out;
  }
  friend bool operator==(const DotMap& a, const DotMap& b) { return a.map_ == b.map_; }

 private:
  std::map<K, S> map_;
};

/// A causal CRDT state (or delta): a dot store and the context that says which dots were seen.
template <class S>
struct Causal {
  S store;
  CausalContext ctx;

  /// this := this ⊔ other.
  void join(const Causal& other) {
    store = S::join(store, ctx, other.store, other.ctx);
    ctx.join(other.ctx);
  }
  friend Causal join(const Causal& a, const Causal& b) {
    Causal out = a;
    out.join(b);
    return out;
  }
  /// Every dot of the store is in the context (the CRDT's basic invariant).
  bool well_formed() const {
    bool ok = true;
    store.for_each_dot([&](const Dot& d) { ok = ok && ctx.contains(d); });
    return ok;
  }
  friend bool operator==(const Causal& a, const Causal& b) { return a.store == b.store && a.ctx == b.ctx; }
};

/// The next dot a replica mints in a context: one above the highest it has seen of itself.
inline Dot next_dot(const CausalContext& ctx, const ReplicaId& r) { return Dot{r, ctx.max_counter(r) + 1}; }

}  // namespace quiver::crdt
