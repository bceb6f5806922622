#pragma once
// Fuzz entry points (each returns whether the input was accepted) shared by the libFuzzer binaries (clang) and the seeded smoke test (any
// compiler). Each feeds untrusted bytes to a decoder and, when the input is accepted, applies it
// to a live replica and checks that the replica's invariants still hold. A crash, sanitizer
// report or abort() is a finding.

#include <cstddef>
#include <cstdint>

namespace quiver::fuzz {

/// Graph delta / state decoder, then merge into a populated replica.
bool graph_delta(const std::uint8_t* data, std::size_t size);
/// A stream of serialized CDR samples (records: topic u8, length u16 LE, the sample's bytes) fed
/// one by one to a Replicator, as a transport delivers them, with time passing between them: the
/// protocol's states a session reaches. Accepted = every record framed and no sample rejected.
bool replication_samples(const std::uint8_t* data, std::size_t size);
/// JSON world files loaded into a replica.
bool world_file(const std::uint8_t* data, std::size_t size);
/// Grammar files: parsed, then used to check a transaction and search for violations.
bool grammar_file(const std::uint8_t* data, std::size_t size);
/// Missions (AGM's .aggt): parsed (errors name the file), checked against a replica (what is
/// missing), and planned for with a small domain (bounded search, every plan verified).
bool mission_file(const std::uint8_t* data, std::size_t size);
/// A CORTEX DSR JSON world imported into a populated replica: refused with the replica unchanged,
/// or imported with its invariants holding; then into an empty replica, exported, and imported
/// again to the same world (a difference aborts). Accepted = imported into the empty replica.
bool dsr_file(const std::uint8_t* data, std::size_t size);
/// An AGM XML world, the same way.
bool agm_file(const std::uint8_t* data, std::size_t size);
/// A schema file (docs/schema.md): refused naming the file, or written back to the same schema, then
/// installed on a populated replica that commits and merges changes under it (a refusal leaves the
/// replica as it was). Accepted = parsed.
bool schema_file(const std::uint8_t* data, std::size_t size);
/// A durable store's log record or snapshot (agents/replica/store/records.h), raw and with a valid checksum.
bool store_record(const std::uint8_t* data, std::size_t size);
/// A .qrec recording: refused with a message, or every recorded change replays into a graph.
bool recording_file(const std::uint8_t* data, std::size_t size);
/// Serialized CDR samples of one DDS topic (0 summary, 1 delta, 2 pull, 3 state, 4 bye), as a rogue
/// participant can publish them: decoded as Cyclone would, then validated and handled by a
/// replicator. Accepted = the replicator took the sample without rejecting it.
bool dds_sample(int topic, const std::uint8_t* data, std::size_t size);

}  // namespace quiver::fuzz
