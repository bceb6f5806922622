// Names of the action API's enumerations.
#include "quiver/agents/runtime/api/action.h"

namespace quiver::agents::inline runtime {

const char* to_string(CancelReason r) {
  switch (r) {
    case CancelReason::kPreconditionGone: return "precondition gone";
    case CancelReason::kLockLost: return "lock lost";
    case CancelReason::kFailed: return "failed";
    case CancelReason::kStopping: return "stopping";
  }
  return "unknown";
}

}  // namespace quiver::agents::inline runtime
