#pragma once
/// @file
/// Causal CRDT types built from dot stores, each with delta mutators: a mutator returns the
/// delta m^δ(X) such that X ⊔ m^δ(X) = m(X).
///  - MVReg<V>: multi-value register (concurrent writes all kept; a deterministic winner);
///  - AWSet<E>: add-wins set;
///  - ORMap<K, S>: observed-remove map of embedded causal CRDTs sharing one context.

#include <algorithm>
#include <vector>

#include "quiver/crdt/dot_store.h"

namespace quiver::crdt {

template <class V>
struct MVReg {
  using State = Causal<DotFun<V>>;

  /// Overwrites every value `x` holds with `v`.
  static State write(const State& x, const ReplicaId& r, V v) {
    State d;
    Dot dot = next_dot(x.ctx, r);
    x.store.for_each_dot([&](const Dot& old) { d.ctx.add(old); });
    d.ctx.add(dot);
    d.store.insert(dot, std::move(v));
    return d;
  }
  /// Removes every value `x` holds.
  static State clear(const State& x) {
    State d;
    x.store.for_each_dot([&](const Dot& old) { d.ctx.add(old); });
    return d;
  }
  static std::vector<V> values(const State& x) {
    std::vector<V> out;
    for (const auto& e : x.store) out.push_back(e.value);
    return out;
  }
  /// The entry with the greatest (fence, counter, replica): the same on every replica with
  /// this state.
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

  static State add(const State& x, const ReplicaId& r, const E& e) {
    State d;
    Dot dot = next_dot(x.ctx, r);
    if (const DotSet* old = x.store.find(e)) old->for_each_dot([&](const Dot& o) { d.ctx.add(o); });
    d.ctx.add(dot);
    d.store[e].insert(dot);
    return d;
  }
  static State remove(const State& x, const E& e) {
    State d;
    if (const DotSet* old = x.store.find(e)) old->for_each_dot([&](const Dot& o) { d.ctx.add(o); });
    return d;
  }
  static bool contains(const State& x, const E& e) { return x.store.find(e) != nullptr; }
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
  static State remove(const State& x, const K& k) {
    State d;
    if (const S* s = x.store.find(k)) s->for_each_dot([&](const Dot& o) { d.ctx.add(o); });
    return d;
  }
  static const S* get(const State& x, const K& k) { return x.store.find(k); }
};

}  // namespace quiver::crdt
