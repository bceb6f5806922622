// A launch file read: its agents (command, arguments, environment, restart policy) and where
// their logs go, every field checked and a mistake named.
#include "quiver/agents/runtime/process/launch_file.h"

#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>

namespace quiver::agents::inline runtime {
namespace {

using nlohmann::json;

Error bad(const std::string& file, const std::string& what) {
  return make_error(ErrorCode::kMalformed, "launch file '" + file + "': " + what);
}

}  // namespace

Result<LaunchFile> load_launch_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kIo, "launch file '" + path + "': cannot be read");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range)
    return bad(path, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object()) return bad(path, "expected an object with \"agents\"");
  LaunchFile f;
  for (const auto& [key, v] : j.items()) {
    if (key == "agents") continue;
    if (key == "logs") {
      if (!v.is_string() || v.get<std::string>().empty()) return bad(path, "logs must be a folder's path");
      f.logs = v.get<std::string>();
    } else if (key == "stop_grace_s") {
      if (!v.is_number() || v.get<double>() < 0 || v.get<double>() > 600)
        return bad(path, "stop_grace_s must be a number of seconds from 0 to 600");
      f.stop_grace_s = v.get<double>();
    } else {
      return bad(path, "unknown field \"" + key + "\" (the fields are agents, logs, stop_grace_s)");
    }
  }
  if (!j.contains("agents") || !j["agents"].is_array() || j["agents"].empty())
    return bad(path, "agents must be a non-empty array");
  static const std::regex kName("[A-Za-z0-9_.-]{1,64}");
  for (std::size_t i = 0; i < j["agents"].size(); ++i) {
    const json& a = j["agents"][i];
    const std::string where = "agents[" + std::to_string(i) + "]";
    if (!a.is_object()) return bad(path, where + " must be an object");
    LaunchAgent la;
    for (const auto& [key, v] : a.items()) {
      if (key == "name") {
        if (!v.is_string() || !std::regex_match(v.get<std::string>(), kName))
          return bad(path, where + ".name must be 1 to 64 letters, digits, '_', '.' or '-' (it names the log file)");
        la.name = v.get<std::string>();
      } else if (key == "command") {
        if (!v.is_string() || v.get<std::string>().empty()) return bad(path, where + ".command must be a program");
        la.command = v.get<std::string>();
      } else if (key == "args") {
        if (!v.is_array()) return bad(path, where + ".args must be an array of strings");
        for (const json& x : v) {
          if (!x.is_string()) return bad(path, where + ".args must be an array of strings");
          la.args.push_back(x.get<std::string>());
        }
      } else if (key == "env") {
        if (!v.is_object()) return bad(path, where + ".env must be an object of strings");
        for (const auto& [k, x] : v.items()) {
          if (!x.is_string() || k.empty() || k.find('=') != std::string::npos)
            return bad(path, where + ".env must be an object of strings");
          la.env[k] = x.get<std::string>();
        }
      } else if (key == "restart") {
        const std::string r = v.is_string() ? v.get<std::string>() : "";
        if (r == "never") la.restart = Restart::kNever;
        else if (r == "on-failure") la.restart = Restart::kOnFailure;
        else if (r == "always") la.restart = Restart::kAlways;
        else return bad(path, where + ".restart must be never, on-failure or always");
      } else if (key == "max_restarts") {
        if (!v.is_number_integer() || v.get<int>() < 0) return bad(path, where + ".max_restarts must be a count");
        la.max_restarts = v.get<int>();
      } else if (key == "restart_delay_s" || key == "start_after_s") {
        if (!v.is_number() || v.get<double>() < 0 || v.get<double>() > 3600)
          return bad(path, where + "." + key + " must be a number of seconds from 0 to 3600");
        (key == "restart_delay_s" ? la.restart_delay_s : la.start_after_s) = v.get<double>();
      } else {
        return bad(path, where + ": unknown field \"" + key +
                             "\" (the fields are name, command, args, env, restart, max_restarts, restart_delay_s, "
                             "start_after_s)");
      }
    }
    if (la.name.empty()) return bad(path, where + " has no name");
    for (const LaunchAgent& other : f.agents)
      if (other.name == la.name) return bad(path, where + ": a second agent named '" + la.name + "'");
    if (la.command.empty() && la.args.empty()) return bad(path, where + " has neither command nor args");
    f.agents.push_back(std::move(la));
  }
  return f;
}

}  // namespace quiver::agents::inline runtime
