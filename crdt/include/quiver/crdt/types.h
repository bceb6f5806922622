#pragma once
/// @file
/// Causal CRDT types built from dot stores, each with delta mutators: a mutator returns the
/// delta m^δ(X) such that X ⊔ m^δ(X) = m(X).
///  - MVReg<V>: multi-value register (concurrent writes all kept; a deterministic winner);
///  - AWSet<E>: add-wins set;
///  - ORMap<K, S>: observed-remove map of embedded causal CRDTs sharing one context.
///
/// Every mutator takes the replica's full state `x` and returns a delta to join into it (and to
/// ship to peers); it never changes `x`. Mutators that mint a dot take the minting replica `r`:
/// @pre for those, `x` is r's own state (its context holds every dot r minted), so that
/// next_dot() is fresh. Threading: pure functions over values; thread-safe on distinct states.

#include <algorithm>
#include <vector>

#include "quiver/crdt/dot_store.h"

namespace quiver::crdt {

template <class V>
struct MVReg {
  using State = Causal<DotFun<V>>;

  /// Overwrites every value `x` holds with `v`.
  /// @returns a delta holding (next_dot(x.ctx, r), v) whose context also covers x's old dots.
  static State write(const State& x, const ReplicaId& r, V v) {
    State d;
    Dot dot = next_dot(x.ctx, r);
    x.store.for_each_dot([&](const Dot& old) { d.ctx.add(old); });
    d.ctx.add(dot);
    d.store.insert(dot, std::move(v));
    return d;
  }
  /// Removes every value `x` holds.
  /// @returns a delta with no entry whose context covers x's current dots.
  static State clear(const State& x) {
    State d;
    x.store.for_each_dot([&](const Dot& old) { d.ctx.add(old); });
    return d;
  }
  /// @returns every concurrent value, in store order (not winner order).
  static std::vector<V> values(const State& x) {
    std::vector<V> out;
    for (const auto& e : x.store) out.push_back(e.value);
    return out;
  }
  /// The entry with the greatest (fence, counter, replica): the same on every replica with
  /// this state.
  /// @returns that entry (pointing into `x`), or nullptr if the register is empty.
  static const Entry<V>* winner(const State& x) {
    const Entry<V>* best = nullptr;
    for (const auto& e : x.store)
      if (best == nullptr || entry_less(*best, e)) best = &e;
    return best;
  }
};

template <class E>
struct AWSet {
  using Store = DotMap<E, DotSet>;
  using State = Causal<Store>;

  /// Adds `e` (add-wins against a concurrent remove).
  /// @returns a delta with a fresh dot for `e` that also covers e's old dots.
  static State add(const State& x, const ReplicaId& r, const E& e) {
    State d;
    Dot dot = next_dot(x.ctx, r);
    if (const DotSet* old = x.store.find(e)) old->for_each_dot([&](const Dot& o) { d.ctx.add(o); });
    d.ctx.add(dot);
    d.store[e].insert(dot);
    return d;
  }
  /// Removes `e` as observed in `x` (concurrent adds survive).
  /// @returns a delta with no entry whose context covers e's dots (empty if `e` is absent).
  static State remove(const State& x, const E& e) {
    State d;
    if (const DotSet* old = x.store.find(e)) old->for_each_dot([&](const Dot& o) { d.ctx.add(o); });
    return d;
  }
  /// @returns true if `e` is in the set.
  static bool contains(const State& x, const E& e) { return x.store.find(e) != nullptr; }
  /// @returns the elements, in E's order.
  static std::vector<E> elements(const State& x) {
    std::vector<E> out;
    for (const auto& [e, dots] : x.store) out.push_back(e);
    return out;
  }
};

template <class K, class S>
struct ORMap {
  using Store = DotMap<K, S>;
  using State = Causal<Store>;

  /// Applies an embedded delta mutator `f(const Causal<S>& inner) -> Causal<S>` to key `k`.
  /// `inner` is k's store (empty if absent) under x's whole context.
  /// @returns f's delta placed under key `k` (no key if its store is empty).
  template <class F>
  static State apply(const State& x, const K& k, F&& f) {
    Causal<S> inner;
    if (const S* s = x.store.find(k)) inner.store = *s;
    inner.ctx = x.ctx;
    Causal<S> di = f(inner);
    State d;
    if (!di.store.empty()) d.store[k] = std::move(di.store);
    d.ctx = std::move(di.ctx);
    return d;
  }
  /// Removes key `k` as observed in `x` (concurrent updates to it survive).
  /// @returns a delta with no entry whose context covers k's dots.
  static State remove(const State& x, const K& k) {
    State d;
    if (const S* s = x.store.find(k)) s->for_each_dot([&](const Dot& o) { d.ctx.add(o); });
    return d;
  }
  /// @returns k's store in `x`, or nullptr.
  static const S* get(const State& x, const K& k) { return x.store.find(k); }
};

}  // namespace quiver::crdt
