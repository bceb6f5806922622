// The AGM keys of a scenario file: the settings (humans, their rate, the reach hysteresis, the
// mission, the person who puts a mug back) and the parameters of the checks.
#include <tuple>

#include "agm_run.h"

namespace quiver::agents::inline apps::agm::internal {
namespace {

Error bad(const std::string& source, const std::string& pointer, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, source + ":" + pointer + ": " + what};
}

}  // namespace

Status read_settings(const nlohmann::json& j, const std::string& source, AgmScenario& s) {
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "humans" && it.key() != "humans_hz" && it.key() != "reach_off_m" &&
        it.key() != "mission" && it.key() != "put_back_s")
      return bad(source, "/" + it.key(), "unknown key");
  if (j.contains("mission")) {
    if (!j["mission"].is_string() ||
        (j["mission"] != "" && j["mission"] != std::string(kCleanTable)))
      return bad(source, "/mission", "expected \"\" or \"clean-table\"");
    s.mission = j["mission"].get<std::string>();
  }
  if (j.contains("humans")) {
    if (!j["humans"].is_boolean()) return bad(source, "/humans", "expected true or false");
    s.humans = j["humans"].get<bool>();
  }
  for (auto [k, out, lo, hi] : {std::tuple{"humans_hz", &s.humans_hz, 1.0, 200.0},
                                std::tuple{"reach_off_m", &s.reach_off_m, 0.10, 1.0},
                                std::tuple{"put_back_s", &s.put_back_s, 0.0, 86'400.0}}) {
    if (!j.contains(k)) continue;
    if (!j[k].is_number() || j[k].get<double>() < lo || j[k].get<double>() > hi)
      return bad(source, std::string("/") + k,
                 "expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    *out = j[k].get<double>();
  }
  return {};
}

nlohmann::json write_settings(const AgmScenario& s) {
  return {{"humans", s.humans},
          {"humans_hz", s.humans_hz},
          {"reach_off_m", s.reach_off_m},
          {"mission", s.mission},
          {"put_back_s", s.put_back_s}};
}

void read_check_params(const nlohmann::json& c, AgmChecks& out) {
  out.exact_crossings = c.value("exact_crossings", out.exact_crossings);
  out.crossing_lag_ms = c.value("crossing_lag_ms", out.crossing_lag_ms);
  out.expect_pause = c.value("expect_pause", out.expect_pause);
  out.motion_allowance_ms = c.value("motion_allowance_ms", out.motion_allowance_ms);
}

nlohmann::json write_checks(const AgmChecks& c) {
  nlohmann::json j = {{"exact_crossings", c.exact_crossings},
                      {"crossing_lag_ms", c.crossing_lag_ms},
                      {"expect_pause", c.expect_pause},
                      {"motion_allowance_ms", c.motion_allowance_ms}};
  for (const char* on :
       {"finished", "converged", "end_state", "moved_matches_odometry", "no_grasp_while_driving",
        "reach", "grasps", "room_changes", "human_poses_delivered", "plan"})
    j[on] = true;
  return j;
}

}  // namespace quiver::agents::inline apps::agm::internal
