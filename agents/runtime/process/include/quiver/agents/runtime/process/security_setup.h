#pragma once
/// @file
/// One call that makes a DDS replica secure from a key directory made by `quiver keys`
/// (docs/security.md): DDS Security with the agent's credentials, and graph-level permissions
/// with signed deltas.

#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline runtime {

/// Sets `o.dds.security` to agent `o.name`'s credentials in `dir` and `o.permissions` to an
/// Admission that signs this agent's deltas with its key, verifies every received delta against
/// its origin's certificate, and checks every change against `dir`/policy.json (when there is
/// none, every authenticated agent may change anything). Errors name the file at fault.
/// Any thread, before DdsReplica::create(o).
/// @pre `o.name` is the agent's name (its credentials are looked up under it).
/// @returns the error of reading the credentials, the key, the identities or the policy (e.g.
///          kNotFound, kIo, kMalformed); `o` is unchanged on error.
Status enable_security(DdsReplicaOptions& o, const std::string& dir);

}  // namespace quiver::agents
