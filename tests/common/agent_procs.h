#pragma once
// Real `quiver agent` processes for tests: start them, read their JSON status lines, wait for
// conditions with bounded timeouts (never fixed sleeps), ask a `quiver dump` observer.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "quiver/agents/runtime/process/subprocess.h"

namespace quiver::tools {

using agents::Subprocess;

using json = nlohmann::json;

struct AgentProc {
  std::string name;
  Subprocess proc;
  json last;  // latest status line
};

class AgentProcs {
 public:
  std::unique_ptr<AgentProc> start(const std::string& name, std::uint32_t domain, std::vector<std::string> extra = {},
                                   const std::string& stderr_path = "") {
    std::vector<std::string> argv = {QUIVER_BIN, "agent", "--name", name, "--domain", std::to_string(domain)};
    if (std::find(extra.begin(), extra.end(), "--status-ms") == extra.end()) argv.insert(argv.end(), {"--status-ms", "100"});
    argv.insert(argv.end(), extra.begin(), extra.end());
    auto p = Subprocess::spawn(argv, stderr_path);
    EXPECT_TRUE(p.has_value());
    auto a = std::make_unique<AgentProc>();
    a->name = name;
    a->proc = std::move(*p);
    return a;
  }
  // Reads every pending status line of every agent.
  static void poll(std::vector<std::unique_ptr<AgentProc>>& agents) {
    for (auto& a : agents) {
      if (!a) continue;
      while (auto line = a->proc.read_line(0)) {
        auto j = json::parse(*line, nullptr, false);
        if (j.is_object()) a->last = j;
      }
    }
  }
  // Polls the agents' status every `interval_ms` until `done()` holds; false on timeout.
  template <class Pred>
  static bool poll_until(std::vector<std::unique_ptr<AgentProc>>& agents, int timeout_ms,
                         int interval_ms, Pred&& done) {
    auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(interval_ms));
      poll(agents);
      if (done()) return true;
    }
    return false;
  }
  // Waits until every running agent has stopped writing and reports the same digest, at least
  // `min_nodes` nodes and `peers` live peers; returns that digest or "" on timeout.
  static std::string wait_converged(std::vector<std::unique_ptr<AgentProc>>& agents, int timeout_ms,
                                    std::size_t peers, std::size_t min_nodes = 1) {
    std::string d;
    auto same = [&] {
      d.clear();
      for (auto& a : agents) {
        if (!a->last.is_object() || a->last["churning"].get<bool>() ||
            a->last["peers"].get<std::size_t>() < peers ||
            a->last["nodes"].get<std::size_t>() < min_nodes)
          return false;
        std::string x = a->last["digest"];
        if (d.empty()) d = x;
        if (x != d) return false;
      }
      return true;
    };
    if (poll_until(agents, timeout_ms, 100, same)) return d;
    for (auto& a : agents)
      std::fprintf(stderr, "  %s: %s\n", a->name.c_str(), a->last.is_object() ? a->last.dump().c_str() : "(no status)");
    return "";
  }
  static std::string dump_digest(std::uint32_t domain) {
    auto p = Subprocess::spawn({QUIVER_BIN, "dump", "--digest", "--domain", std::to_string(domain), "--timeout", "20"});
    if (!p) return "";
    auto line = p->read_line(30'000);
    p->wait(5'000);
    return line.value_or("");
  }
};


}  // namespace quiver::tools
