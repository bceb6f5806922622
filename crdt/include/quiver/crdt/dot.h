#pragma once
/// @file
/// Replica ids and dots: the unique names of events in a causal CRDT.
///
/// Threading: plain values; every function here is thread-safe.

#include <compare>
#include <cstdint>
#include <functional>
#include <string>

#include "quiver/base/hash.h"

namespace quiver::crdt {

/// The greatest counter (of a dot or a sequence number) Quiver produces or accepts: 2^53 - 1, so
/// that every counter is also exact as a JSON number. Decoders refuse anything above it, and a
/// replica refuses to mint beyond it rather than wrap.
inline constexpr std::uint64_t kMaxCounter = (std::uint64_t{1} << 53) - 1;
/// Lamport clocks follow counters seen from others only up to this ceiling: a peer that publishes
/// counters near kMaxCounter cannot exhaust anyone else's counter space (its later writes may then
/// win over ours, but ours keep flowing). 2^52 counters take over a century at a billion per second.
inline constexpr std::uint64_t kClockCeiling = std::uint64_t{1} << 52;

/// A replica is one incarnation of one agent. An agent restarted without durable state comes
/// back under a new incarnation, so it can never mint a dot it minted before.
struct ReplicaId {
  std::uint64_t agent = 0;        ///< Stable id of the agent (e.g. the hash of its name).
  std::uint64_t incarnation = 0;  ///< Distinct for every start of the agent.

  friend auto operator<=>(const ReplicaId&, const ReplicaId&) = default;
  friend bool operator==(const ReplicaId&, const ReplicaId&) = default;
  /// @returns true if both agent and incarnation are 0.
  bool is_null() const { return agent == 0 && incarnation == 0; }
  /// @returns "00000000000000ab.3": the agent as 16 hex digits, a dot, the incarnation.
  std::string to_string() const;
  /// Writes to_string() into `out` (replacing its contents; no allocation once `out` holds 24
  /// bytes).
  void write_to(std::string& out) const;
};

/// A dot names one event of one replica: its counter-th. Counters start at 1.
struct Dot {
  ReplicaId replica;
  std::uint64_t counter = 0;

  friend auto operator<=>(const Dot&, const Dot&) = default;
  friend bool operator==(const Dot&, const Dot&) = default;
  /// @returns true if the counter is 0 (no event has it), whatever the replica.
  bool is_null() const { return counter == 0; }
  /// @returns "00000000000000ab.3:42": the replica as ReplicaId::to_string(), ':', the counter.
  std::string to_string() const;
};

/// Cheap pre-mix of a replica id (combined with a counter and mixed once by hash_value(Dot)).
/// @returns a value that is not itself a good hash; feed it to mix64().
constexpr std::uint64_t r_hash_seed(const ReplicaId& r) {
  return r.agent * 0xff51afd7ed558ccdULL ^ (r.incarnation + 0x632be59bd9b4e019ULL);
}

/// Total order used to pick deterministic winners among concurrent events: the counter first
/// (counters are Lamport clocks in Quiver's graph, so "later" wins), then the replica id.
/// @returns true if `a` comes before `b`; a strict total order on dots.
inline bool lamport_less(const Dot& a, const Dot& b) {
  if (a.counter != b.counter) return a.counter < b.counter;
  return a.replica < b.replica;
}

/// @returns a well-mixed 64-bit hash of `r`, the same in every process.
inline std::uint64_t hash_value(const ReplicaId& r) {
  return mix64(r.agent ^ (r.incarnation * 0x9e3779b97f4a7c15ULL));
}
/// @returns a well-mixed 64-bit hash of `d`, the same in every process.
inline std::uint64_t hash_value(const Dot& d) {
  return mix64(r_hash_seed(d.replica) ^ (d.counter * 0xc2b2ae3d27d4eb4fULL));
}

}  // namespace quiver::crdt

template <>
struct std::hash<quiver::crdt::ReplicaId> {
  /// @returns hash_value(r).
  std::size_t operator()(const quiver::crdt::ReplicaId& r) const noexcept { return hash_value(r); }
};
template <>
struct std::hash<quiver::crdt::Dot> {
  /// @returns hash_value(d).
  std::size_t operator()(const quiver::crdt::Dot& d) const noexcept { return hash_value(d); }
};
