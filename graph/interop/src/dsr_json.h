#pragma once
// Private: reading CORTEX DSR JSON, shared by the importer's parts: numbers in every form files
// use, attribute entries and their values (with or without type codes), ids, and RT links' poses.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "plan.h"
#include "quiver/base/result.h"
#include "quiver/graph/value.h"

namespace quiver::interop::internal {

using json = nlohmann::ordered_json;

/// A JSON pointer's reference token (RFC 6901: '~' as ~0, '/' as ~1).
std::string token(std::string_view key);

/// A number or a decimal string (',' accepted as the decimal point, as CORTEX's reader does).
bool as_double(const json& j, double& out);
/// An integer, a number with a fraction (rounded; `rounded` tells), or the same as a string.
bool as_integer(const json& j, std::int64_t& out, bool& rounded);
/// A non-negative integer, or digits in a string (CORTEX writes uint64 values as strings).
bool as_uint64(const json& j, std::uint64_t& out);
/// The numbers of an array (numbers or numeric strings), or of a string of numbers separated by
/// white space (the oldest files).
bool as_doubles(const json& j, std::vector<double>& out);


/// One attribute entry with its name and where it is, before conversion (RT links read some of
/// them as poses).
struct RawAttr {
  std::string name;
  json entry;  ///< {"value": V[, "type": CODE]} (array entries also hold their "key")
  std::string where;
};

/// The entries of an "attribute" / "linkAttribute" member (an object or an array of entries).
Result<std::vector<RawAttr>> raw_attributes(const json& j, const std::string& where);
/// The entries' values, converted (`warnings` receives notes such as rounding).
Result<Attrs> convert(const std::vector<RawAttr>& raw, std::vector<std::string>& warnings);
/// A CORTEX id: digits in a string or an unsigned number, as canonical decimal text.
Result<std::string> node_id(const json& j, const std::string& where);

/// The pose of an RT link, from whichever form it has, and its other attributes.
struct RtPose {
  graph::Pose pose;
  std::vector<RawAttr> rest;
};

/// The pose of an RT link from its attributes `raw`, in any of the layouts in use.
Result<RtPose> rt_pose(std::vector<RawAttr> raw, const std::string& where, std::vector<std::string>& warnings,
                       double metres_per_unit);

/// The link attributes the pose is read from (and history-pack bookkeeping), in any layout.
bool is_pose_key(std::string_view k);

}  // namespace quiver::interop::internal
