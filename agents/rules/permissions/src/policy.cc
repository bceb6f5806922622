// The graph-level permissions policy: its JSON file read, and the first rule matching an action and target
// deciding whether an agent may take it.
#include "quiver/agents/rules/permissions/policy.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "quiver/base/hash.h"

namespace quiver::agents::inline rules::permissions {
namespace {

constexpr std::pair<Action, const char*> kActions[] = {
    {Action::kCreate, "create"}, {Action::kDelete, "delete"}, {Action::kWrite, "write"},
    {Action::kEdge, "edge"},     {Action::kRt, "rt"},         {Action::kLock, "lock"},
};

bool matches(const std::string& pattern, const std::string& text) { return pattern == "*" || pattern == text; }

std::string hex(std::uint64_t v) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

const char* to_string(Action a) {
  for (const auto& [action, name] : kActions)
    if (action == a) return name;
  return "?";
}

Policy Policy::allow_all() { return Policy{}; }

Result<Policy> Policy::parse(std::string_view text, const std::string& where) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range)
    return make_error(ErrorCode::kMalformed, where + ": JSON syntax error: " + e.what());
  }
  auto fail = [&](const std::string& what) { return make_error(ErrorCode::kMalformed, where + ": " + what); };
  if (!j.is_object()) return fail("a policy is a JSON object with \"default\" and \"rules\"");
  for (const auto& [key, v] : j.items())
    if (key != "default" && key != "rules") return fail("unknown key \"" + key + "\" (expected \"default\", \"rules\")");
  Policy p;
  if (j.contains("default")) {
    const auto& d = j["default"];
    if (!d.is_string() || (d != "allow" && d != "deny")) return fail("\"default\" must be \"allow\" or \"deny\"");
    p.default_allow_ = d == "allow";
  }
  if (j.contains("rules")) {
    const auto& rules = j["rules"];
    if (!rules.is_array()) return fail("\"rules\" must be an array");
    for (std::size_t i = 0; i < rules.size(); ++i) {
      const auto& r = rules[i];
      const std::string at = "rule " + std::to_string(i + 1);
      if (!r.is_object()) return fail(at + " is not an object");
      for (const auto& [key, v] : r.items())
        if (key != "action" && key != "target" && key != "agents")
          return fail(at + ": unknown key \"" + key + "\" (expected \"action\", \"target\", \"agents\")");
      if (!r.contains("action") || !r["action"].is_string()) return fail(at + ": \"action\" (a string) is missing");
      if (!r.contains("target") || !r["target"].is_string()) return fail(at + ": \"target\" (a string) is missing");
      if (!r.contains("agents") || !r["agents"].is_array()) return fail(at + ": \"agents\" (an array of names) is missing");
      Rule rule;
      const std::string action = r["action"];
      bool known = false;
      for (const auto& [a, name] : kActions)
        if (action == name) {
          rule.action = a;
          known = true;
        }
      if (!known) return fail(at + ": unknown action \"" + action + "\" (create, delete, write, edge, rt, lock)");
      rule.target = r["target"];
      if (rule.target.empty()) return fail(at + ": the target is empty");
      if (rule.action == Action::kWrite) {
        const auto dot = rule.target.find('.');
        if (dot == std::string::npos) {
          rule.name = rule.target;
        } else {
          rule.type = rule.target.substr(0, dot);
          rule.name = rule.target.substr(dot + 1);
          if (rule.type.empty() || rule.name.empty())
            return fail(at + ": the target \"" + rule.target + "\" is not ATTRIBUTE, TYPE.ATTRIBUTE or TYPE.*");
        }
      } else {
        if (rule.target.find('.') != std::string::npos)
          return fail(at + ": a " + action + " rule's target is a type, not \"" + rule.target + "\"");
        rule.name = rule.target;
      }
      for (const auto& a : r["agents"]) {
        if (!a.is_string() || a.get<std::string>().empty()) return fail(at + ": \"agents\" holds something that is not a name");
        const std::string name = a;
        rule.agents.push_back(name);
        if (name == "*") {
          rule.any_agent = true;
        } else {
          rule.agent_ids.push_back(fnv1a64(name));
          p.names_.emplace(fnv1a64(name), name);
        }
      }
      p.rules_.push_back(std::move(rule));
    }
  }
  return p;
}

Result<Policy> Policy::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kNotFound, path + ": cannot open the policy file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path);
}

int Policy::rule_for(Action action, graph::Symbol type, graph::Symbol name) const {
  const std::uint64_t key = static_cast<std::uint64_t>(action) << 58 ^ static_cast<std::uint64_t>(type.index()) << 29 ^
                            static_cast<std::uint64_t>(name.index());
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  const std::string& t = type.str();
  const std::string& n = name.str();
  int found = -1;
  for (std::size_t i = 0; i < rules_.size() && found < 0; ++i) {
    const Rule& r = rules_[i];
    if (r.action != action) continue;
    const bool hit = action == Action::kWrite ? (r.type.empty() || matches(r.type, t)) && matches(r.name, n)
                                              : matches(r.name, t);
    if (hit) found = static_cast<int>(i);
  }
  if (cache_.size() < (1u << 16)) cache_.emplace(key, found);
  return found;
}

Status Policy::check(std::uint64_t agent, Action action, graph::Symbol type, graph::Symbol name) const {
  const int i = rule_for(action, type, name);
  bool allowed = default_allow_;
  if (i >= 0) {
    const Rule& r = rules_[static_cast<std::size_t>(i)];
    allowed = r.any_agent;
    for (std::uint64_t a : r.agent_ids) allowed = allowed || a == agent;
  }
  if (allowed) return {};
  std::string what = std::string(to_string(action)) + " ";
  const std::string t = type.is_null() ? "(untyped)" : type.str();
  if (action == Action::kWrite) what += "'" + name.str() + "' on '" + t + "'";
  else what += "'" + t + "'";
  const std::string why = i >= 0 ? "rule " + std::to_string(i + 1) + " (" + to_string(rules_[i].action) + " " +
                                       rules_[i].target + ") reserves it to others"
                                 : "no rule grants it and the default is deny";
  return make_error(ErrorCode::kPermissionDenied, "agent '" + agent_name(agent) + "' may not " + what + ": " + why);
}

void Policy::learn_name(const std::string& name) { names_.emplace(fnv1a64(name), name); }

std::string Policy::agent_name(std::uint64_t agent) const {
  auto it = names_.find(agent);
  return it != names_.end() ? it->second : hex(agent);
}

}  // namespace quiver::agents::inline rules::permissions
