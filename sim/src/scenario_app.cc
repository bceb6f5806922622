// An app's registration with the simulator: roles, checks, workloads, settings, shared state.
#include "quiver/sim/scenario_app.h"

namespace quiver::sim {

ScenarioApp& ScenarioApp::role(std::string name, RoleFactory make) {
  roles_[std::move(name)] = std::move(make);
  return *this;
}

ScenarioApp& ScenarioApp::check(std::string name, CheckFactory make) {
  checks_[std::move(name)] = std::move(make);
  return *this;
}

ScenarioApp& ScenarioApp::workload(std::string name, WorkloadFactory make) {
  workloads_[std::move(name)] = std::move(make);
  return *this;
}

ScenarioApp& ScenarioApp::default_agents(std::vector<std::string> roles) {
  default_agents_ = std::move(roles);
  return *this;
}

ScenarioApp& ScenarioApp::default_world(std::string world_json) {
  default_world_ = std::move(world_json);
  return *this;
}

ScenarioApp& ScenarioApp::settings(std::function<Status(const nlohmann::json&, const std::string&)> check) {
  settings_ = std::move(check);
  return *this;
}

ScenarioApp& ScenarioApp::on_start(std::function<Status(ScenarioRun&)> fn) {
  on_start_ = std::move(fn);
  return *this;
}

ScenarioApp& ScenarioApp::done_when(std::function<bool(ScenarioRun&)> fn) {
  done_when_ = std::move(fn);
  return *this;
}

ScenarioApp& ScenarioApp::report(std::function<void(ScenarioRun&, nlohmann::json&)> fn) {
  report_ = std::move(fn);
  return *this;
}

std::vector<std::string> ScenarioApp::roles() const {
  std::vector<std::string> out;
  for (const auto& [r, _] : roles_) out.push_back(r);
  return out;
}

std::vector<std::string> ScenarioApp::check_names() const {
  std::vector<std::string> out;
  for (const auto& [c, _] : checks_) out.push_back(c);
  return out;
}

const ScenarioApp::CheckFactory* ScenarioApp::check_factory(const std::string& c) const {
  auto it = checks_.find(c);
  return it == checks_.end() ? nullptr : &it->second;
}

const ScenarioApp::WorkloadFactory* ScenarioApp::workload_factory(const std::string& w) const {
  auto it = workloads_.find(w);
  return it == workloads_.end() ? nullptr : &it->second;
}

Status ScenarioApp::check_settings(const nlohmann::json& app_keys, const std::string& source) const {
  if (settings_) return settings_(app_keys, source);
  for (auto it = app_keys.begin(); it != app_keys.end(); ++it)
    return Error{ErrorCode::kInvalidArgument, source + ":/" + it.key() + ": unknown key"};
  return {};
}

}  // namespace quiver::sim
