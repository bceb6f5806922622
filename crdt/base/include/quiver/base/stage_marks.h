#pragma once
/// @file
/// Where a change's time goes between two processes (`quiver bench dds --stages`): each layer a
/// change crosses marks the moment it did, on CLOCK_MONOTONIC (shared by the processes of one
/// machine). Off unless a benchmark process turns it on; then one mark is one clock read. Only
/// the latest mark of each stage is kept: the benchmark spaces its changes so that one crosses at
/// a time. Never read by logic the simulator runs.
#include <cstdint>

namespace quiver::inline base::stage_marks {

enum class Stage : std::uint8_t {
  kEncoded,   ///< writer: the local delta encoded (after the commit applied it)
  kSigned,    ///< writer: signed (with identities; else right after kEncoded)
  kWritten,   ///< writer: DDS's write of the delta returned
  kWoken,     ///< reader: the owner thread's wait for samples returned
  kTaken,     ///< reader: the delta sample taken and converted from DDS's form
  kDecoded,   ///< reader: the delta's payload decoded and checked against its message
  kAdmitted,  ///< reader: past duplicate, equivocation and admission checks
  kMerging,   ///< reader: the graph merge (and the change events it raises) begins
  kCount
};

/// Turns marking on for this process (a benchmark role, before it opens its replica).
void enable();
/// Records the time now for `s` when enabled.
void mark(Stage s);
/// The latest mark of `s` (0: none yet).
std::int64_t at(Stage s);

}  // namespace quiver::inline base::stage_marks
