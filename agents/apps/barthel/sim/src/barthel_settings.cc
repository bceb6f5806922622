// The Barthel keys of a scenario file: the patient (a script or a seed) and the timing.
#include "barthel_settings.h"

#include <tuple>
#include <utility>

namespace quiver::agents::inline apps::barthel::internal {
namespace {

Error bad(const std::string& source, const std::string& pointer, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, source + ":" + pointer + ": " + what};
}

}  // namespace

Status read_settings(const nlohmann::json& j, const std::string& source, PatientScript& script,
                     ScenarioTiming& timing) {
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "patient" && it.key() != "timing") return bad(source, "/" + it.key(), "unknown key");
  if (j.contains("patient")) {
    const nlohmann::json& p = j["patient"];
    if (!p.is_object()) return bad(source, "/patient", "expected {\"script\": {...}} or {\"seed\": N}");
    if (p.contains("script")) {
      auto s = PatientScript::from_json(p["script"]);
      if (!s.ok()) return bad(source, "/patient/script", s.error().message);
      script = *s;
    } else if (p.contains("seed")) {
      if (!p["seed"].is_number_unsigned()) return bad(source, "/patient/seed", "expected a non-negative integer");
      const auto seed = p["seed"].get<std::uint64_t>();
      script = p.value("varied", false) ? PatientScript::varied(seed) : PatientScript::random(seed);
    } else {
      return bad(source, "/patient", "expected \"script\" or \"seed\"");
    }
  }
  if (j.contains("timing")) {
    const nlohmann::json& t = j["timing"];
    if (!t.is_object()) return bad(source, "/timing", "expected an object");
    for (auto [k, out, lo, hi] : {std::tuple{"words_ms", &timing.words_ms, 0.0, 10'000.0},
                                  std::tuple{"base_ms", &timing.base_ms, 0.0, 10'000.0},
                                  std::tuple{"answer_timeout_s", &timing.answer_timeout_s, 0.1, 600.0},
                                  std::tuple{"person_hz", &timing.person_hz, 1.0, 200.0}}) {
      if (!t.contains(k)) continue;
      if (!t[k].is_number() || t[k].get<double>() < lo || t[k].get<double>() > hi)
        return bad(source, std::string("/timing/") + k,
                   "expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      *out = t[k].get<double>();
    }
    if (t.contains("joints")) {
      if (!t["joints"].is_boolean()) return bad(source, "/timing/joints", "expected true or false");
      timing.joints = t["joints"].get<bool>();
    }
    if (t.contains("think_ms")) {
      const nlohmann::json& th = t["think_ms"];
      if (!th.is_array() || th.size() != 2 || !th[0].is_number() || !th[1].is_number() || th[0].get<double>() < 0 ||
          th[1].get<double>() < th[0].get<double>())
        return bad(source, "/timing/think_ms", "expected [min, max] milliseconds");
      script.think_min_ns = static_cast<std::int64_t>(th[0].get<double>() * 1e6);
      script.think_max_ns = static_cast<std::int64_t>(th[1].get<double>() * 1e6);
    }
  }
  return {};
}

nlohmann::json write_settings(const PatientScript& script, const ScenarioTiming& timing) {
  return {{"patient", {{"script", script.to_json()}}},
          {"timing",
           {{"words_ms", timing.words_ms},
            {"base_ms", timing.base_ms},
            {"answer_timeout_s", timing.answer_timeout_s},
            {"person_hz", timing.person_hz},
            {"joints", timing.joints}}}};
}

}  // namespace quiver::agents::inline apps::barthel::internal
