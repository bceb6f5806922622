// CORTEX DSR RT links: an RT link's pose read from whichever form its attributes have
// (vectors, scalars, a history pack), in metres, and the keys those forms use.

#include <algorithm>
#include <array>
#include <cmath>

#include "dsr_json.h"
#include "euler_xyz.h"
#include "plan.h"
#include "text_values.h"

namespace quiver::interop::internal {

Result<RtPose> rt_pose(std::vector<RawAttr> raw, const std::string& where, std::vector<std::string>& warnings,
                       double metres_per_unit) {
  struct Form {
    const char* translation;
    const char* rotation;
  };
  static constexpr Form kForms[] = {{"rt_translation", "rt_rotation_euler_xyz"},
                                    {"translation", "rotation_euler_xyz"},
                                    {"trans", "rot"}};
  static constexpr const char* kScalars[] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  const RawAttr* vec[2] = {nullptr, nullptr};
  const Form* form = nullptr;
  const RawAttr* scalar[6] = {};
  const RawAttr* stamps = nullptr;
  const RawAttr* head = nullptr;
  RtPose out;
  for (const RawAttr& a : raw) {
    bool used = false;
    for (const Form& f : kForms) {
      for (int k = 0; k < 2; ++k) {
        if (a.name != (k == 0 ? f.translation : f.rotation)) continue;
        if (form && form != &f)
          return malformed(a.where, std::string("the RT link gives its pose twice (\"") + form->translation + "\" and \"" +
                                        a.name + "\")");
        form = &f;
        vec[k] = &a;
        used = true;
      }
    }
    for (int k = 0; k < 6; ++k)
      if (a.name == kScalars[k]) scalar[k] = &a, used = true;
    if (a.name == "rt_timestamps") stamps = &a, used = true;
    if (a.name == "rt_head_index") head = &a, used = true;
    if (!used) out.rest.push_back(a);
  }
  const bool any_scalar = std::any_of(std::begin(scalar), std::end(scalar), [](const RawAttr* a) { return a; });
  if (form && any_scalar)
    return malformed(where, std::string("the RT link gives its pose twice (\"") + form->translation + "\" and tx...rz)");
  std::array<double, 3> t{0, 0, 0}, r{0, 0, 0};
  // The value of an entry: {"value": V} or a {"key", "value"} array entry alike.
  auto value_of = [](const RawAttr& a) -> const json& { return a.entry["value"]; };
  if (any_scalar) {
    for (int k = 0; k < 6; ++k) {
      if (!scalar[k]) continue;
      if (!scalar[k]->entry.contains("value")) return malformed(scalar[k]->where, "missing \"value\"");
      double d;
      if (!as_double(value_of(*scalar[k]), d)) return malformed(scalar[k]->where, "expected a number");
      (k < 3 ? t[k] : r[k - 3]) = d;
    }
  } else if (form) {
    std::vector<double> v[2];
    for (int k = 0; k < 2; ++k) {
      if (!vec[k]) continue;
      if (!vec[k]->entry.contains("value")) return malformed(vec[k]->where, "missing \"value\"");
      if (!as_doubles(value_of(*vec[k]), v[k]) || v[k].size() < 3 || v[k].size() % 3 != 0)
        return malformed(vec[k]->where, "expected 3 numbers (or a history pack of 3 per sample)");
    }
    if (!vec[0] || !vec[1])
      warnings.push_back(where + ": the RT link has \"" + (vec[0] ? form->translation : form->rotation) + "\" but no \"" +
                         (vec[0] ? form->rotation : form->translation) + "\": taken as 0");
    const std::size_t samples = (vec[0] ? v[0].size() : v[1].size()) / 3;
    if (vec[0] && vec[1] && v[0].size() != v[1].size())
      return malformed(vec[1]->where, "the history packs of translation and rotation differ in length (" +
                                                     std::to_string(v[0].size()) + " and " +
                                                     std::to_string(v[1].size()) + " numbers)");
    // The newest sample: the greatest of rt_timestamps; without them, rt_head_index; else the
    // first (what CORTEX reads then).
    std::size_t pick = 0;
    bool picked = samples == 1;
    if (!picked && stamps) {
      if (!stamps->entry.contains("value")) return malformed(stamps->where, "missing \"value\"");
      const json& ts = value_of(*stamps);
      std::vector<std::uint64_t> times;
      if (ts.is_array())
        for (const json& e : ts) {
          std::uint64_t x;
          if (!as_uint64(e, x)) return malformed(stamps->where, "expected an array of unsigned integers");
          times.push_back(x);
        }
      if (!ts.is_array() || times.size() != samples)
        return malformed(stamps->where, "expected one time stamp per sample (" + std::to_string(samples) + ")");
      if (std::any_of(times.begin(), times.end(), [&](std::uint64_t x) { return x != times[0]; })) {
        pick = static_cast<std::size_t>(std::max_element(times.begin(), times.end()) - times.begin());
        picked = true;
      }
    }
    if (!picked && head) {
      std::int64_t h;
      bool rounded;
      if (!head->entry.contains("value") || !as_integer(value_of(*head), h, rounded) || rounded || h < 0 || h % 3 != 0 ||
          static_cast<std::uint64_t>(h) / 3 >= samples)
        return malformed(head->where, "expected the index of a sample's first number (0, 3, 6... below " +
                                          std::to_string(3 * samples) + ")");
      pick = static_cast<std::size_t>(h / 3);
      picked = true;
    }
    if (!picked)
      warnings.push_back(where + ": a history pack of " + std::to_string(samples) +
                         " samples without time stamps or head index: the first sample is taken");
    for (int i = 0; i < 3; ++i) {
      if (vec[0]) t[i] = v[0][3 * pick + i];
      if (vec[1]) r[i] = v[1][3 * pick + i];
    }
  } else {
    warnings.push_back(where + ": the RT link has no rt_translation / rt_rotation_euler_xyz: identity");
  }
  if (!form && (stamps || head))
    warnings.push_back(where + ": rt_timestamps / rt_head_index without a history pack: ignored");
  out.pose = internal::pose_from_xyz(t, r, metres_per_unit);
  return out;
}

/// The link attributes the pose is read from (and history-pack bookkeeping), in any layout: an
/// `rt:` attribute of that name cannot be written back onto an RT link.
bool is_pose_key(std::string_view k) {
  for (const char* p : {"rt_translation", "rt_rotation_euler_xyz", "translation", "rotation_euler_xyz", "trans", "rot",
                        "tx", "ty", "tz", "rx", "ry", "rz", "rt_timestamps", "rt_head_index"})
    if (k == p) return true;
  return false;
}

}  // namespace quiver::interop::internal
