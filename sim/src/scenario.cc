#include "quiver/sim/scenario.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "quiver/agents/apps/barthel/checks.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/devices/memory_pager.h"
#include "quiver/agents/devices/memory_result_store.h"
#include "quiver/sim/agent_host.h"
#include "quiver/sim/simulator.h"

namespace quiver::sim {

namespace barthel = agents::barthel;
namespace devices = agents::devices;
using nlohmann::json;

std::string FaultEvent::describe() const {
  std::ostringstream o;
  o << "t=" << at_s << "s ";
  switch (kind) {
    case Kind::kPartition: {
      o << "partition";
      for (const auto& g : groups) {
        o << " {";
        for (std::size_t i = 0; i < g.size(); ++i) o << (i ? "," : "") << g[i];
        o << "}";
      }
      break;
    }
    case Kind::kHeal: o << "heal"; break;
    case Kind::kKill: o << "kill -9 " << agent; break;
    case Kind::kRestart: o << "restart " << agent; break;
    case Kind::kLoss: o << "loss " << loss; break;
  }
  return o.str();
}

namespace {

Error bad(const std::string& source, const std::string& pointer, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, source + ":" + pointer + ": " + what};
}

bool known_role(const std::string& r) {
  for (const auto& k : barthel::role_names())
    if (k == r) return true;
  return false;
}

}  // namespace

Result<Scenario> Scenario::parse(const json& j, const std::string& source) {
  Scenario s;
  if (!j.is_object()) return bad(source, "/", "a scenario is a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    static const char* kKeys[] = {"name", "agents", "world", "patient", "faults", "checks", "timing", "limit_s"};
    bool ok = false;
    for (const char* k : kKeys) ok = ok || it.key() == k;
    if (!ok) return bad(source, "/" + it.key(), "unknown key");
  }
  if (j.contains("name")) {
    if (!j["name"].is_string()) return bad(source, "/name", "expected a string");
    s.name = j["name"].get<std::string>();
  }
  if (j.contains("agents")) {
    if (!j["agents"].is_array() || j["agents"].empty()) return bad(source, "/agents", "expected a non-empty array of roles");
    s.agents.clear();
    for (std::size_t i = 0; i < j["agents"].size(); ++i) {
      const auto& a = j["agents"][i];
      if (!a.is_string() || !known_role(a.get<std::string>()))
        return bad(source, "/agents/" + std::to_string(i), "not a role (planner, speech, panel, person, patient)");
      s.agents.push_back(a.get<std::string>());
    }
  }
  if (j.contains("world")) {
    if (!j["world"].is_string()) return bad(source, "/world", "expected a file name");
    s.world_file = j["world"].get<std::string>();
  }
  if (j.contains("patient")) {
    const json& p = j["patient"];
    if (!p.is_object()) return bad(source, "/patient", "expected {\"script\": {...}} or {\"seed\": N}");
    if (p.contains("script")) {
      auto script = barthel::PatientScript::from_json(p["script"]);
      if (!script.ok()) return bad(source, "/patient/script", script.error().message);
      s.script = *script;
    } else if (p.contains("seed")) {
      if (!p["seed"].is_number_unsigned()) return bad(source, "/patient/seed", "expected a non-negative integer");
      const auto seed = p["seed"].get<std::uint64_t>();
      s.script = p.value("varied", false) ? barthel::PatientScript::varied(seed) : barthel::PatientScript::random(seed);
    } else {
      return bad(source, "/patient", "expected \"script\" or \"seed\"");
    }
  }
  if (j.contains("faults")) {
    if (!j["faults"].is_array()) return bad(source, "/faults", "expected an array");
    for (std::size_t i = 0; i < j["faults"].size(); ++i) {
      const json& f = j["faults"][i];
      const std::string where = "/faults/" + std::to_string(i);
      if (!f.is_object() || !f.contains("at_s") || !f["at_s"].is_number() || f["at_s"].get<double>() < 0)
        return bad(source, where, "expected {\"at_s\": T >= 0, and one of partition, heal, kill, restart, loss}");
      FaultEvent e;
      e.at_s = f["at_s"].get<double>();
      if (f.contains("partition")) {
        e.kind = FaultEvent::Kind::kPartition;
        const json& gs = f["partition"];
        if (!gs.is_array() || gs.empty()) return bad(source, where + "/partition", "expected groups of agent names");
        for (std::size_t g = 0; g < gs.size(); ++g) {
          if (!gs[g].is_array()) return bad(source, where + "/partition/" + std::to_string(g), "expected an array of names");
          std::vector<std::string> group;
          for (std::size_t k = 0; k < gs[g].size(); ++k) {
            if (!gs[g][k].is_string() || !known_role(gs[g][k].get<std::string>()))
              return bad(source, where + "/partition/" + std::to_string(g) + "/" + std::to_string(k), "not an agent");
            group.push_back(gs[g][k].get<std::string>());
          }
          e.groups.push_back(group);
        }
      } else if (f.contains("heal")) {
        e.kind = FaultEvent::Kind::kHeal;
      } else if (f.contains("kill") || f.contains("restart")) {
        const bool kill = f.contains("kill");
        e.kind = kill ? FaultEvent::Kind::kKill : FaultEvent::Kind::kRestart;
        const json& a = f[kill ? "kill" : "restart"];
        if (!a.is_string() || !known_role(a.get<std::string>()))
          return bad(source, where + (kill ? "/kill" : "/restart"), "not an agent");
        e.agent = a.get<std::string>();
      } else if (f.contains("loss")) {
        e.kind = FaultEvent::Kind::kLoss;
        if (!f["loss"].is_number() || f["loss"].get<double>() < 0 || f["loss"].get<double>() > 0.9)
          return bad(source, where + "/loss", "expected a probability in [0, 0.9]");
        e.loss = f["loss"].get<double>();
      } else {
        return bad(source, where, "no fault (partition, heal, kill, restart or loss)");
      }
      s.faults.push_back(e);
    }
  }
  if (j.contains("checks")) {
    const json& c = j["checks"];
    if (!c.is_object()) return bad(source, "/checks", "expected an object");
    if (c.contains("never_speaking_absent_ms")) {
      if (!c["never_speaking_absent_ms"].is_number_integer()) return bad(source, "/checks/never_speaking_absent_ms", "expected an integer");
      s.checks.never_speaking_absent_ms = c["never_speaking_absent_ms"].get<std::int64_t>();
    }
    for (auto [k, out] : {std::pair{"no_item_asked_twice", &s.checks.no_item_asked_twice},
                          std::pair{"result_matches_script", &s.checks.result_matches_script}}) {
      if (!c.contains(k)) continue;
      if (!c[k].is_boolean()) return bad(source, std::string("/checks/") + k, "expected true or false");
      *out = c[k].get<bool>();
    }
    if (c.contains("status")) {
      if (!c["status"].is_string()) return bad(source, "/checks/status", "expected completed or clinician_called");
      s.checks.status = c["status"].get<std::string>();
    }
    if (c.contains("total")) {
      if (!c["total"].is_number_integer()) return bad(source, "/checks/total", "expected an integer");
      s.checks.total = c["total"].get<int>();
    }
  }
  if (j.contains("timing")) {
    const json& t = j["timing"];
    if (!t.is_object()) return bad(source, "/timing", "expected an object");
    for (auto [k, out, lo, hi] : {std::tuple{"words_ms", &s.timing.words_ms, 0.0, 10'000.0},
                                  std::tuple{"base_ms", &s.timing.base_ms, 0.0, 10'000.0},
                                  std::tuple{"answer_timeout_s", &s.timing.answer_timeout_s, 0.1, 600.0},
                                  std::tuple{"person_hz", &s.timing.person_hz, 1.0, 200.0}}) {
      if (!t.contains(k)) continue;
      if (!t[k].is_number() || t[k].get<double>() < lo || t[k].get<double>() > hi)
        return bad(source, std::string("/timing/") + k, "expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      *out = t[k].get<double>();
    }
    if (t.contains("joints")) {
      if (!t["joints"].is_boolean()) return bad(source, "/timing/joints", "expected true or false");
      s.timing.joints = t["joints"].get<bool>();
    }
    if (t.contains("think_ms")) {
      const json& th = t["think_ms"];
      if (!th.is_array() || th.size() != 2 || !th[0].is_number() || !th[1].is_number() || th[0].get<double>() < 0 ||
          th[1].get<double>() < th[0].get<double>())
        return bad(source, "/timing/think_ms", "expected [min, max] milliseconds");
      s.script.think_min_ns = static_cast<std::int64_t>(th[0].get<double>() * 1e6);
      s.script.think_max_ns = static_cast<std::int64_t>(th[1].get<double>() * 1e6);
    }
  }
  if (j.contains("limit_s")) {
    if (!j["limit_s"].is_number() || j["limit_s"].get<double>() <= 0 || j["limit_s"].get<double>() > 86400)
      return bad(source, "/limit_s", "expected seconds in (0, 86400]");
    s.limit_s = j["limit_s"].get<double>();
  }
  return s;
}

Result<Scenario> Scenario::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{ErrorCode::kIo, path + ": cannot open the scenario file"};
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    return Error{ErrorCode::kInvalidArgument, path + ": not JSON: " + e.what()};
  }
  return parse(j, path);
}

json Scenario::to_json() const {
  json j;
  j["name"] = name;
  j["agents"] = agents;
  if (!world_file.empty()) j["world"] = world_file;
  j["patient"] = {{"script", script.to_json()}};
  j["faults"] = json::array();
  for (const FaultEvent& f : faults) {
    json e = {{"at_s", f.at_s}};
    switch (f.kind) {
      case FaultEvent::Kind::kPartition: e["partition"] = f.groups; break;
      case FaultEvent::Kind::kHeal: e["heal"] = true; break;
      case FaultEvent::Kind::kKill: e["kill"] = f.agent; break;
      case FaultEvent::Kind::kRestart: e["restart"] = f.agent; break;
      case FaultEvent::Kind::kLoss: e["loss"] = f.loss; break;
    }
    j["faults"].push_back(e);
  }
  j["checks"] = {{"never_speaking_absent_ms", checks.never_speaking_absent_ms},
                 {"no_item_asked_twice", checks.no_item_asked_twice},
                 {"result_matches_script", checks.result_matches_script}};
  if (checks.status) j["checks"]["status"] = *checks.status;
  if (checks.total) j["checks"]["total"] = *checks.total;
  j["timing"] = {{"words_ms", timing.words_ms}, {"base_ms", timing.base_ms}, {"answer_timeout_s", timing.answer_timeout_s},
                 {"person_hz", timing.person_hz}, {"joints", timing.joints}};
  j["limit_s"] = limit_s;
  return j;
}

Scenario Scenario::random_faults(std::uint64_t seed) {
  Rng rng(seed ^ 0x5ca1ab1e);
  Scenario s;
  s.name = "barthel-faults";
  s.script = barthel::PatientScript::varied(seed);
  s.script.think_min_ns = 150'000'000;
  s.script.think_max_ns = 700'000'000;
  for (auto& l : s.script.leaves) {
    l.after_ns = 100'000'000 + static_cast<std::int64_t>(rng.below(500'000'000));
    l.for_ns = 500'000'000 + static_cast<std::int64_t>(rng.below(2'000'000'000));
  }
  s.timing.words_ms = 40;
  s.timing.base_ms = 100;
  s.timing.answer_timeout_s = 3;
  s.timing.person_hz = 20;
  s.timing.joints = false;
  s.limit_s = 600;
  const std::vector<std::string> robot = {"planner", "speech", "panel", "person"};
  auto at = [&](double lo, double hi) { return lo + rng.uniform() * (hi - lo); };
  if (rng.chance(0.6)) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kLoss;
    e.at_s = at(0, 10);
    e.loss = 0.3 * rng.uniform();
    s.faults.push_back(e);
  }
  const int partitions = static_cast<int>(rng.below(3));
  for (int p = 0; p < partitions; ++p) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kPartition;
    e.at_s = at(2, 40);
    std::vector<std::string> a, b;
    for (const auto& n : s.agents) (rng.chance(0.5) ? a : b).push_back(n);
    if (a.empty() || b.empty()) continue;
    e.groups = {a, b};
    s.faults.push_back(e);
    FaultEvent h;
    h.kind = FaultEvent::Kind::kHeal;
    h.at_s = e.at_s + at(0.3, 3);
    s.faults.push_back(h);
  }
  const int kills = static_cast<int>(rng.below(3));
  for (int k = 0; k < kills; ++k) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kKill;
    e.agent = robot[rng.below(robot.size())];
    e.at_s = at(1, 40);
    s.faults.push_back(e);
    FaultEvent r = e;
    r.kind = FaultEvent::Kind::kRestart;
    r.at_s = e.at_s + at(0.1, 3);
    s.faults.push_back(r);
  }
  return s;
}

json ScenarioResult::to_json() const {
  json j = {{"name", name},
            {"seed", seed},
            {"passed", passed},
            {"failures", failures},
            {"status", status},
            {"total", total},
            {"expected_status", expected_status},
            {"expected_total", expected_total},
            {"finished_s", finished_s},
            {"max_speaking_absent_ms", max_speaking_absent_ms},
            {"interruptions", interruptions},
            {"kills", kills},
            {"partitions", partitions},
            {"rejected", rejected}};
  return j;
}

ScenarioResult run_scenario(const Scenario& s, std::uint64_t seed,
                            std::function<void(std::int64_t, const std::string&)> log) {
  ScenarioResult r;
  r.name = s.name;
  r.seed = seed;
  auto fail = [&](const std::string& f) {
    if (r.failures.size() < 20) r.failures.push_back(f);
  };

  std::string world(barthel::world_json());
  if (!s.world_file.empty()) {
    std::ifstream in(s.world_file);
    if (!in) {
      fail(s.world_file + ": cannot open the world file");
      return r;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    world = ss.str();
  }

  // Devices that outlive an agent's incarnation: the clinician's pager and the result store.
  devices::MemoryResultStore store;
  devices::MemoryPager pager;
  AgentHost* host_ptr = nullptr;
  int patient = -1;
  auto truth = [&]() -> const graph::Graph* { return patient >= 0 && host_ptr ? host_ptr->graph(patient) : nullptr; };

  barthel::RoleOptions ro;
  ro.truth = truth;
  ro.script = s.script;
  ro.store = &store;
  ro.pager = &pager;
  ro.sim_ns_per_word = static_cast<std::int64_t>(s.timing.words_ms * 1e6);
  ro.sim_base_ns = static_cast<std::int64_t>(s.timing.base_ms * 1e6);
  ro.planner.answer_timeout_ns = static_cast<std::int64_t>(s.timing.answer_timeout_s * 1e9);
  ro.planner.needs.clear();
  for (const char* n : {"speech", "panel", "person"})
    for (const auto& a : s.agents)
      if (a == n) ro.planner.needs.push_back(n);
  ro.person.rate_hz = s.timing.person_hz;
  ro.person.joints = s.timing.joints;

  std::vector<SimAgentSpec> specs;
  for (const std::string& role : s.agents)
    specs.push_back({role, [ro, role]() -> std::unique_ptr<agents::Agent> { auto a = barthel::make_role(role, ro); return a.ok() ? std::move(*a) : nullptr; }});
  AgentHostOptions ho;
  ho.seed = seed;
  ho.replicator = SimConfig::default_replicator();
  ho.locks.lease_ns = 1'000'000'000;
  ho.world_json = world;
  ho.log = log;
  AgentHost host(std::move(specs), ho);
  host_ptr = &host;
  patient = host.index("patient");
  if (Status st = host.start(); !st.ok()) {
    fail(st.error().to_string());
    return r;
  }
  host.on_action_event([&](int i, const agents::ActionEvent& e) {
    if (host.name(i) == "speech" && e.kind == agents::ActionEvent::Kind::kCancelled) ++r.interruptions;
  });

  for (const FaultEvent& f : s.faults) {
    host.at(static_cast<std::int64_t>(f.at_s * 1e9), [&host, &r, f, log] {
      if (log) log(host.now(), "fault: " + f.describe());
      switch (f.kind) {
        case FaultEvent::Kind::kPartition: host.partition(f.groups); ++r.partitions; break;
        case FaultEvent::Kind::kHeal: host.heal(); break;
        case FaultEvent::Kind::kKill:
          if (int i = host.index(f.agent); i >= 0) {
            host.kill(i);
            ++r.kills;
          }
          break;
        case FaultEvent::Kind::kRestart:
          if (int i = host.index(f.agent); i >= 0 && !host.up(i)) host.restart(i);
          break;
        case FaultEvent::Kind::kLoss: host.set_loss(f.loss); break;
      }
    });
  }

  // Check over time: never speaking to the patient while the person has been away too long.
  const int speech = host.index("speech");
  barthel::AbsenceWatch absence;
  host.every(10'000'000, [&] {
    const graph::Graph* t = truth();
    if (!t) return;
    bool speaking = false;
    if (speech >= 0 && host.up(speech) && host.agent(speech)) {
      auto* sp = dynamic_cast<barthel::Speech*>(host.agent(speech));
      speaking = sp && sp->output().playing(host.now()) && barthel::speaking_to_patient(*host.graph(speech));
    }
    absence.sample(host.now(), barthel::patient_present_truth(*t), speaking);
    r.max_speaking_absent_ms = absence.max_ms();
  });

  // Run until the result is stored and the closing words said (or the limit).
  const auto limit = static_cast<std::int64_t>(s.limit_s * 1e9);
  std::int64_t stored_at = -1;
  while (host.now() < limit) {
    host.run_until(host.now() + 100'000'000);
    if (stored_at < 0 && store.last()) stored_at = host.now();
    if (stored_at >= 0 && host.now() - stored_at > 15'000'000'000) break;
  }
  r.rejected = host.rejected();

  // Checks at the end.
  const auto expected = s.script.expected();
  r.expected_status = expected.status;
  r.expected_total = expected.total;
  if (s.checks.never_speaking_absent_ms > 0 && r.max_speaking_absent_ms > static_cast<double>(s.checks.never_speaking_absent_ms))
    fail("spoke to the patient " + std::to_string(r.max_speaking_absent_ms) + " ms after the person had left (limit " +
         std::to_string(s.checks.never_speaking_absent_ms) + " ms)");
  auto result = store.last();
  if (!result) {
    fail("no result stored within " + std::to_string(s.limit_s) + " s of virtual time");
  } else {
    r.status = result->status;
    r.total = result->total;
    r.finished_s = stored_at / 1e9;
    if (s.checks.status && *s.checks.status != result->status)
      fail("status " + result->status + ", expected " + *s.checks.status);
    if (s.checks.total && *s.checks.total != result->total)
      fail("total " + std::to_string(result->total) + ", expected " + std::to_string(*s.checks.total));
    if (s.checks.result_matches_script)
      for (const auto& d : barthel::result_differences(*result, expected)) fail(d);
  }
  if (s.checks.no_item_asked_twice) {
    // Read the patient's replica (never killed): every prompt the robot said to the end.
    const graph::Graph* g = truth();
    if (!g) fail("no replica to check the questions in");
    else
      for (const auto& d : barthel::questions_asked_twice(*g)) fail(d);
  }
  r.passed = r.failures.empty();
  return r;
}

}  // namespace quiver::sim
