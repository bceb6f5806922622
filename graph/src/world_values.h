#pragma once
// Private: attribute values in world files (JSON), read with checks and written back; shared by
// loading and saving worlds.

#include <nlohmann/json.hpp>
#include <string>

#include "quiver/graph/value.h"

namespace quiver::graph::internal {

using json = nlohmann::json;

// Semantic errors carry a JSON pointer to the offending value.
struct Failure {
  std::string where;
  std::string what;
};

/// Reads one attribute value; on failure fills `f` (where: a JSON pointer under `where`).
bool parse_value(const json& j, const std::string& where, Value& out, Failure& f);
/// A value as world files write it.
json value_to_json(const Value& v);

}  // namespace quiver::graph::internal
