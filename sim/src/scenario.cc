// Scenario files: the generic keys, with the app's own handed to the app.
#include "quiver/sim/scenario.h"

#include <fstream>
#include <set>

#include "file_error.h"

namespace quiver::sim {
namespace {

using internal::file_error;

constexpr const char* kGenericKeys[] = {"name", "app", "agents", "world", "faults", "workloads", "checks", "limit_s"};

bool generic_key(const std::string& k) {
  for (const char* g : kGenericKeys)
    if (k == g) return true;
  return false;
}

}  // namespace

std::vector<ScenarioAgent> Scenario::agents_of(const ScenarioApp& app) const {
  if (!agents.empty()) return agents;
  std::vector<ScenarioAgent> out;
  for (const auto& r : app.default_agents(settings)) out.push_back({r, r});
  return out;
}

Result<Scenario> Scenario::parse(const nlohmann::json& j, const std::string& source, const ScenarioApp& app) {
  Scenario s;
  s.app = app.name();
  if (!j.is_object()) return file_error(source, "/", "a scenario is a JSON object");
  nlohmann::json app_keys = nlohmann::json::object();
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!generic_key(it.key())) app_keys[it.key()] = it.value();
  if (Status st = app.check_settings(app_keys, source); !st.ok()) return st.error();
  s.settings = app_keys;
  if (j.contains("name")) {
    if (!j["name"].is_string()) return file_error(source, "/name", "expected a string");
    s.name = j["name"].get<std::string>();
  }
  if (j.contains("app")) {
    if (!j["app"].is_string() || j["app"].get<std::string>() != app.name())
      return file_error(source, "/app", "this scenario runs the app '" + app.name() + "'");
  }
  auto roles_list = [&] {
    std::string r;
    for (const auto& n : app.roles()) r += (r.empty() ? "" : ", ") + n;
    return r;
  };
  if (j.contains("agents")) {
    const nlohmann::json& as = j["agents"];
    if (!as.is_array() || as.empty()) return file_error(source, "/agents", "expected a non-empty array of roles");
    std::set<std::string> names;
    for (std::size_t i = 0; i < as.size(); ++i) {
      const std::string where = "/agents/" + std::to_string(i);
      ScenarioAgent a;
      if (as[i].is_string()) {
        a.role = a.name = as[i].get<std::string>();
      } else if (as[i].is_object() && as[i].contains("role") && as[i]["role"].is_string()) {
        a.role = as[i]["role"].get<std::string>();
        a.name = as[i].value("name", a.role);
      } else {
        return file_error(source, where, "expected a role or {\"role\": R, \"name\": N}");
      }
      if (!app.has_role(a.role)) return file_error(source, where, "not a role (" + roles_list() + ")");
      if (!names.insert(a.name).second) return file_error(source, where, "a second agent named '" + a.name + "'");
      s.agents.push_back(a);
    }
  }
  const std::vector<ScenarioAgent> running = s.agents_of(app);
  auto is_agent = [&](const std::string& n) {
    for (const auto& a : running)
      if (a.name == n) return true;
    return false;
  };
  if (j.contains("world")) {
    if (!j["world"].is_string()) return file_error(source, "/world", "expected a file name");
    s.world_file = j["world"].get<std::string>();
  }
  if (j.contains("faults")) {
    if (!j["faults"].is_array()) return file_error(source, "/faults", "expected an array");
    for (std::size_t i = 0; i < j["faults"].size(); ++i) {
      auto f = parse_fault(j["faults"][i], source, "/faults/" + std::to_string(i), is_agent);
      if (!f.ok()) return f.error();
      s.faults.push_back(*f);
    }
  }
  for (const char* section : {"workloads", "checks"}) {
    if (!j.contains(section)) continue;
    const nlohmann::json& c = j[section];
    if (!c.is_object()) return file_error(source, std::string("/") + section, "expected an object of names and parameters");
    const bool checks = std::string(section) == "checks";
    for (auto it = c.begin(); it != c.end(); ++it) {
      const std::string where = std::string("/") + section + "/" + it.key();
      Status made;
      if (checks) {
        const auto* make = app.check_factory(it.key());
        if (make == nullptr) return file_error(source, where, "not a check of the app '" + app.name() + "'");
        auto c = (*make)(it.value(), source + ":" + where);
        if (!c.ok()) made = c.error();
      } else {
        const auto* make = app.workload_factory(it.key());
        if (make == nullptr) return file_error(source, where, "not a workload of the app '" + app.name() + "'");
        auto w = (*make)(it.value(), source + ":" + where);
        if (!w.ok()) made = w.error();
      }
      if (!made.ok()) return made.error();
    }
    (checks ? s.checks : s.workloads) = c;
  }
  if (j.contains("limit_s")) {
    if (!j["limit_s"].is_number() || j["limit_s"].get<double>() <= 0 || j["limit_s"].get<double>() > 86400)
      return file_error(source, "/limit_s", "expected seconds in (0, 86400]");
    s.limit_s = j["limit_s"].get<double>();
  }
  return s;
}

Result<nlohmann::json> Scenario::read(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{ErrorCode::kIo, path + ": cannot open the scenario file"};
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range)
    return Error{ErrorCode::kInvalidArgument, path + ": not JSON: " + e.what()};
  }
}

Result<Scenario> Scenario::load(const std::string& path, const ScenarioApp& app) {
  auto j = read(path);
  if (!j.ok()) return j.error();
  return parse(*j, path, app);
}

nlohmann::json Scenario::to_json() const {
  nlohmann::json j = settings;
  j["name"] = name;
  if (!app.empty()) j["app"] = app;
  if (!agents.empty()) {
    j["agents"] = nlohmann::json::array();
    for (const auto& a : agents)
      j["agents"].push_back(a.name == a.role ? nlohmann::json(a.role) : nlohmann::json{{"role", a.role}, {"name", a.name}});
  }
  if (!world_file.empty()) j["world"] = world_file;
  j["faults"] = nlohmann::json::array();
  for (const FaultEvent& f : faults) j["faults"].push_back(sim::to_json(f));
  if (!workloads.empty()) j["workloads"] = workloads;
  j["checks"] = checks;
  j["limit_s"] = limit_s;
  return j;
}

}  // namespace quiver::sim
