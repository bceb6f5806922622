#pragma once
/// @file
/// One recorded change: when a replica received it, whose change it is, and the CRDT fragment
/// that made it. Replaying the fragments of a recording in order into an empty graph rebuilds
/// the recorded replica's state after each of them, exactly (merges are deterministic).

#include <cstdint>
#include <string>

#include "quiver/graph/delta.h"

namespace quiver::agents::inline view::recording {

struct RecordedChange {
  std::int64_t t_ns =
      0;  ///< when it was applied, on the recorder's clock (ns since the recording began)
  std::string origin;  ///< the name of the agent whose change it is ("" when unknown)
  /// A delta (kDelta) as published, or a state fragment (kState: the recorded replica's state
  /// when the recording began, or a state transfer it received).
  graph::GraphDelta delta;
};

}  // namespace quiver::agents::inline view::recording
