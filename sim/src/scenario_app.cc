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
  return default_agents([roles = std::move(roles)](const nlohmann::json&) { return roles; });
}

ScenarioApp& ScenarioApp::default_agents(std::function<std::vector<std::string>(const nlohmann::json&)> roles) {
  default_agents_ = std::move(roles);
  return *this;
}

ScenarioApp& ScenarioApp::default_world(std::string world_json) {
  return default_world([world = std::move(world_json)](const nlohmann::json&) { return world; });
}

ScenarioApp& ScenarioApp::default_world(std::function<std::string(const nlohmann::json&)> world_json) {
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

ScenarioApp& ScenarioApp::settle(std::function<void(ScenarioRun&)> fn) {
  settle_ = std::move(fn);
  return *this;
}

ScenarioApp& ScenarioApp::team(std::function<AgentHostOptions::Team(const nlohmann::json&)> fn) {
  team_ = std::move(fn);
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

std::vector<std::string> ScenarioApp::default_agents(const nlohmann::json& settings) const {
  return default_agents_ ? default_agents_(settings) : std::vector<std::string>{};
}

std::string ScenarioApp::default_world(const nlohmann::json& settings) const {
  return default_world_ ? default_world_(settings) : std::string();
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

ScenarioApp::CheckFactory switch_check(std::function<void(ScenarioRun&, std::vector<std::string>&)> finish) {
  struct C final : Check {
    explicit C(std::function<void(ScenarioRun&, std::vector<std::string>&)> f) : fn(std::move(f)) {}
    std::function<void(ScenarioRun&, std::vector<std::string>&)> fn;
    void finish(ScenarioRun& run, std::vector<std::string>& failures) override { fn(run, failures); }
  };
  return [finish = std::move(finish)](const nlohmann::json& p, const std::string& where) -> Result<std::unique_ptr<Check>> {
    if (!p.is_boolean()) return Error{ErrorCode::kInvalidArgument, where + ": expected true or false"};
    if (!p.get<bool>()) return std::unique_ptr<Check>();
    return std::unique_ptr<Check>(std::make_unique<C>(finish));
  };
}

}  // namespace quiver::sim
