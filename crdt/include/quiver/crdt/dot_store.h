#pragma once
/// @file
/// Dot stores and causal CRDTs after Almeida, Shoker and Baquero, "Delta State Replicated Data
/// Types" (2018), section 7: DotSet, DotFun<V> and DotMap<K, S>, each joined under a causal
/// context; Causal<S> pairs a store with its context. A dot in the context but not in the store
/// means "seen and removed", so removals need no tombstones.
///
/// join(s, c, s', c') for a dot set: (s ∩ s') ∪ (s \ c') ∪ (s' \ c); dot functions likewise on
/// their keys; dot maps key by key, dropping keys whose store becomes empty.
///
/// Threading: plain value types without synchronization: const members may run concurrently on
/// one object, a mutation needs exclusive access. Nothing here throws but what V, K or S throw
/// (and std::bad_alloc). Pointers and iterators into a store are invalidated by any mutation.

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
/// @returns true if `a` loses to `b` (the greatest entry wins).
template <class V>
bool entry_less(const Entry<V>& a, const Entry<V>& b) {
  if (a.fence != b.fence) return a.fence < b.fence;
  return lamport_less(a.dot, b.dot);
}

/// A set of dots. Usually one, so stored inline.
class DotSet {
 public:
  /// @returns true if the set holds no dot.
  bool empty() const { return dots_.empty(); }
  /// @returns the number of dots.
  std::size_t size() const { return dots_.size(); }
  /// @returns true if `d` is in the set (a linear scan).
  bool contains(const Dot& d) const {
    for (const Dot& x : dots_)
      if (x == d) return true;
    return false;
  }
  /// Adds `d` unless present.
  void insert(const Dot& d) {
    if (!contains(d)) dots_.push_back(d);
  }
  /// Removes `d` (order of the others not kept).
  /// @returns true if `d` was present.
  bool erase(const Dot& d) {
    for (Dot* it = dots_.begin(); it != dots_.end(); ++it)
      if (*it == d) {
        dots_.swap_erase(it);
        return true;
      }
    return false;
  }
  /// @returns the first dot, in no particular order.
  const Dot* begin() const { return dots_.begin(); }
  /// @returns one past the last dot.
  const Dot* end() const { return dots_.end(); }
  /// Calls f(dot) for every dot. @pre `f` does not modify this set.
  template <class F>
  void for_each_dot(F&& f) const {
    for (const Dot& d : dots_) f(d);
  }

  /// @returns the join of (a, ca) and (b, cb): (a ∩ b) ∪ (a \ cb) ∪ (b \ ca).
  static DotSet join(const DotSet& a, const CausalContext& ca, const DotSet& b, const CausalContext& cb) {
    DotSet out;
    for (const Dot& d : a.dots_)
      if (b.contains(d) || !cb.contains(d)) out.dots_.push_back(d);
    for (const Dot& d : b.dots_)
      if (!a.contains(d) && !ca.contains(d)) out.dots_.push_back(d);
    return out;
  }
  /// @returns true if both hold the same dots, in any order.
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
  /// @returns true if the map holds no entry.
  bool empty() const { return entries_.empty(); }
  /// @returns the number of entries (concurrent values).
  std::size_t size() const { return entries_.size(); }
  /// @returns the first entry, in insertion order (not winner order).
  const EntryT* begin() const { return entries_.begin(); }
  /// @returns one past the last entry.
  const EntryT* end() const { return entries_.end(); }
  /// @returns the first entry, mutable. @pre callers may change values, never an entry's dot.
  EntryT* begin() { return entries_.begin(); }
  /// @returns one past the last entry.
  EntryT* end() { return entries_.end(); }
  /// @returns the entry with dot `d`, or nullptr.
  const EntryT* find(const Dot& d) const {
    for (const EntryT& e : entries_)
      if (e.dot == d) return &e;
    return nullptr;
  }
  /// Adds the entry (d, v, fence) unless an entry with dot `d` exists (then nothing changes).
  void insert(const Dot& d, V v, std::uint64_t fence = 0) {
    if (find(d) == nullptr) entries_.emplace_back(EntryT{d, std::move(v), fence});
  }
  /// Removes the entry with dot `d`, keeping the others' order.
  /// @returns true if it was present.
  bool erase(const Dot& d) {
    for (EntryT* it = entries_.begin(); it != entries_.end(); ++it)
      if (it->dot == d) {
        entries_.erase(it);
        return true;
      }
    return false;
  }
  /// Removes every entry.
  void clear() { entries_.clear(); }
  /// Removes the entries for which pred(entry) is true, keeping the others' order.
  /// @returns how many were removed.
  template <class Pred>
  std::size_t erase_if(Pred pred) {
    return entries_.erase_if(pred);
  }
  /// Calls f(dot) for every entry's dot. @pre `f` does not modify this map.
  template <class F>
  void for_each_dot(F&& f) const {
    for (const EntryT& e : entries_) f(e.dot);
  }

  /// @returns the join of (a, ca) and (b, cb), dot by dot as for DotSet; an entry both hold is
  ///          taken from `a`.
  static DotFun join(const DotFun& a, const CausalContext& ca, const DotFun& b, const CausalContext& cb) {
    DotFun out;
    for (const EntryT& e : a.entries_)
      if (b.find(e.dot) != nullptr || !cb.contains(e.dot)) out.entries_.push_back(e);
    for (const EntryT& e : b.entries_)
      if (a.find(e.dot) == nullptr && !ca.contains(e.dot)) out.entries_.push_back(e);
    return out;
  }
  /// @returns true if both hold the same (dot, value, fence) entries, in any order.
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
  /// @returns true if the map holds no key.
  bool empty() const { return map_.empty(); }
  /// @returns the number of keys.
  std::size_t size() const { return map_.size(); }
  /// @returns the store of key `k`, or nullptr.
  const S* find(const K& k) const {
    auto it = map_.find(k);
    return it == map_.end() ? nullptr : &it->second;
  }
  /// @returns the store of key `k`, inserting an empty one if absent.
  /// @pre the caller fills the store or erase()s the key: an empty store must not stay.
  S& operator[](const K& k) { return map_[k]; }
  /// Removes key `k` and its store (nothing if absent).
  void erase(const K& k) { map_.erase(k); }
  /// @returns an iterator over (key, store) pairs in key order.
  auto begin() const { return map_.begin(); }
  /// @returns the end iterator.
  auto end() const { return map_.end(); }
  /// Calls f(dot) for every dot of every store, keys in order. @pre `f` does not modify this map.
  template <class F>
  void for_each_dot(F&& f) const {
    for (const auto& [k, s] : map_) s.for_each_dot(f);
  }

  /// @returns the join of (a, ca) and (b, cb), key by key with S::join; keys whose joined store
  ///          is empty are dropped.
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
  /// @returns true if both hold the same keys with equal stores.
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
  /// @pre both are well_formed() (the join relies on it).
  void join(const Causal& other) {
    store = S::join(store, ctx, other.store, other.ctx);
    ctx.join(other.ctx);
  }
  /// @returns a ⊔ b (a copy of `a` joined with `b`). @pre both are well_formed().
  friend Causal join(const Causal& a, const Causal& b) {
    Causal out = a;
    out.join(b);
    return out;
  }
  /// Every dot of the store is in the context (the CRDT's basic invariant).
  /// @returns true if it holds.
  bool well_formed() const {
    bool ok = true;
    store.for_each_dot([&](const Dot& d) { ok = ok && ctx.contains(d); });
    return ok;
  }
  /// @returns true if stores and contexts are equal.
  friend bool operator==(const Causal& a, const Causal& b) { return a.store == b.store && a.ctx == b.ctx; }
};

/// The next dot a replica mints in a context: one above the highest it has seen of itself.
/// @pre `ctx` holds every dot `r` has minted (it is r's own full context), else the dot repeats.
/// @returns Dot{r, ctx.max_counter(r) + 1}.
inline Dot next_dot(const CausalContext& ctx, const ReplicaId& r) { return Dot{r, ctx.max_counter(r) + 1}; }

}  // namespace quiver::crdt
