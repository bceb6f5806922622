// quiver mission check, quiver plan, quiver bench planner: missions (AGM's .aggt targets) and the
// planner (docs/planner.md).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "grammar_schema.h"
#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/planner/planner.h"
#include "quiver/agents/rules/planner/plan_replay.h"
#include "quiver/interop/any_world.h"
#include "quiver/interop/interop.h"

namespace quiver::tools {
namespace {

using agents::planner::PlannerOptions;
using agents::planner::PlanResult;

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

using interop::load_any_world_file;

// --schema (docs/schema.md): the mission, and the grammar when there is one, against the shared
// vocabulary; an error listing what it does not declare.
Status fits_schema(const std::string& path, const agents::Mission& m, const agents::Grammar* g) {
  if (path.empty()) return {};
  auto s = agents::schema::Schema::load(path);
  if (!s.ok()) return s.error();
  std::vector<std::string> errors;
  pattern_schema_errors(m.pattern, *s, "mission", errors);
  if (g != nullptr)
    for (std::string& e : grammar_schema_errors(*g, *s)) errors.push_back(std::move(e));
  if (errors.empty()) return {};
  std::string what = "the schema " + path + " does not declare what the mission or the grammar uses:";
  for (const std::string& e : errors) what += "\n  " + e;
  return make_error(ErrorCode::kInvalidArgument, what);
}

struct MissionArgs {
  std::string world, mission, domain, schema;
  std::vector<std::string> include_dirs;
  bool json = false;
};

void run_mission_check(const MissionArgs& a) {
  auto fail = [](const std::string& msg) {
    std::cerr << "error: " << msg << "\n";
    set_exit_code(2);
  };
  auto m = agents::load_mission_file(a.mission);
  if (!m.ok()) return fail(m.error().message);
  agents::TypeSystem types;
  std::optional<agents::Grammar> domain;
  if (!a.domain.empty()) {
    auto g = agents::load_grammar_file(a.domain, a.include_dirs);
    if (!g.ok()) return fail(g.error().message);
    types = g->types;
    domain = std::move(*g);
  }
  if (Status s = fits_schema(a.schema, *m, domain ? &*domain : nullptr); !s.ok()) return fail(s.error().message);
  graph::Graph g(graph::ReplicaId{0x6d697373696f6eULL, 1});
  if (Status s = load_any_world_file(g, a.world); !s.ok()) return fail(s.error().message);
  agents::MissionReport r = agents::check_mission(*m, g, types);
  if (a.json) {
    nlohmann::json j;
    j["holds"] = r.holds;
    j["satisfied"] = r.satisfied;
    j["total"] = r.total;
    j["missing"] = r.missing;
    j["binding"] = nlohmann::json::object();
    for (const auto& [var, node] : r.binding) j["binding"][var] = node;
    std::cout << j.dump() << std::endl;
  } else {
    std::cout << a.mission << ": " << (r.holds ? "holds" : "does not hold") << " (" << r.satisfied << " of "
              << r.total << " nodes and links)\n";
    for (const auto& [var, node] : r.binding) std::cout << "  " << var << " = " << node << "\n";
    for (const std::string& line : r.missing) std::cout << "  missing: " << line << "\n";
    if (!r.exhaustive) std::cout << "  (the search for the closest assignment stopped at its budget)\n";
    for (const std::string& n : m->notes) std::cout << "  note: " << n << "\n";
  }
  set_exit_code(r.holds ? 0 : 1);
}

struct PlanArgs {
  std::string grammar, world, mission, schema;
  std::vector<std::string> include_dirs;
  double max_time_s = 60;
  int max_world_increment = 5;
  std::size_t max_expansions = 0;
  bool verify = true;
  bool json = false;
  bool no_heuristic = false;
  int runs = 1;
  std::string replay;
};

struct Problem {
  agents::Grammar grammar;
  agents::Mission mission;
  std::unique_ptr<graph::Graph> graph;
};

Result<Problem> load_problem(const std::string& grammar, const std::string& world, const std::string& mission,
                             const std::vector<std::string>& include_dirs) {
  Problem p;
  auto g = agents::load_grammar_file(grammar, include_dirs);
  if (!g.ok()) return g.error();
  p.grammar = std::move(*g);
  auto m = agents::load_mission_file(mission);
  if (!m.ok()) return m.error();
  p.mission = std::move(*m);
  p.graph = std::make_unique<graph::Graph>(graph::ReplicaId{0x706c616e6e6572ULL, 1});
  if (Status s = load_any_world_file(*p.graph, world); !s.ok()) return s.error();
  return p;
}

void run_plan(const PlanArgs& a) {
  auto fail = [](const std::string& msg) {
    std::cerr << "error: " << msg << "\n";
    set_exit_code(2);
  };
  PlannerOptions o;
  o.max_world_increment = a.max_world_increment;
  o.max_expansions = a.max_expansions;
  o.heuristic = !a.no_heuristic;
  if (a.max_time_s > 0) {
    o.max_time_ns = static_cast<std::int64_t>(a.max_time_s * 1e9);
    o.clock = steady_ns;
  }
  PlanResult best;
  std::vector<double> times;
  std::optional<Problem> p;
  std::unique_ptr<agents::planner::Domain> domain;
  agents::symbolic::World world;
  std::optional<agents::CompiledMission> cm;
  for (int run = 0; run < std::max(1, a.runs); ++run) {
    // Everything a planning request does counts: reading the files, the world into a replica,
    // compiling the rules and the mission, searching, decomposing.
    const std::int64_t t0 = steady_ns();
    auto loaded = load_problem(a.grammar, a.world, a.mission, a.include_dirs);
    if (!loaded.ok()) return fail(loaded.error().message);
    if (run == 0)
      if (Status s = fits_schema(a.schema, loaded->mission, &loaded->grammar); !s.ok()) return fail(s.error().message);
    p = std::move(*loaded);
    world = agents::symbolic::read_world(*p->graph, p->grammar.types);
    domain = std::make_unique<agents::planner::Domain>(p->grammar, world.vocabulary);
    auto compiled = agents::compile_mission(p->mission, world);
    if (!compiled.ok()) return fail(compiled.error().message);
    cm = std::move(*compiled);
    best = agents::planner::plan(*domain, world.state, *cm, o);
    times.push_back(static_cast<double>(steady_ns() - t0) / 1e9);
  }
  std::sort(times.begin(), times.end());
  const double median = times[times.size() / 2];
  std::string verified = "skipped";
  if (best.found() && a.verify) {
    agents::GrammarChecker checker(p->grammar);
    Status s = agents::planner::verify_plan(*p->graph, checker, world, best, p->mission);
    verified = s.ok() ? "ok" : s.error().message;
  }
  // Another planner's plan (AGM's `.plan` lines), replayed with our meaning of the rules.
  nlohmann::json replayed;
  if (!a.replay.empty()) {
    auto text = interop::read_file("plan --replay", a.replay);
    if (!text.ok()) return fail(text.error().message);
    agents::symbolic::State s = world.state;
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start < text->size()) {
      auto end = text->find('\n', start);
      if (end == std::string::npos) end = text->size();
      std::string line = text->substr(start, end - start);
      start = end + 1;
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
      if (line.empty() || (line[0] == '#' && line.rfind("#!", 0) != 0)) continue;
      if (line.rfind("#!", 0) == 0) continue;  // a decomposed hierarchical step: its steps follow
      lines.push_back(line);
    }
    replayed["steps"] = nlohmann::json::array();
    bool applies = true;
    for (const std::string& line : lines) {
      auto step = agents::planner::parse_step(line, *domain, world);
      std::string verdict = "applies";
      if (!step.ok()) {
        verdict = step.error().message;
        applies = false;
      } else if (auto next = domain->apply(s, *step)) {
        s = std::move(*next);
      } else {
        verdict = "does not apply here";
        applies = false;
      }
      replayed["steps"].push_back({{"step", line}, {"verdict", verdict}});
      if (!applies) break;
    }
    replayed["applies"] = applies;
    replayed["reaches_mission"] = applies && agents::mission_holds(s, world.vocabulary, *cm);
  }
  if (a.json) {
    nlohmann::json j;
    j["outcome"] = agents::planner::to_string(best.outcome);
    j["cost"] = best.cost;
    j["search_cost"] = best.search_cost;
    j["length"] = best.steps.size();
    j["expansions"] = best.expansions;
    j["generated"] = best.generated;
    j["searches"] = best.searches;
    j["time_s"] = median;
    j["times_s"] = times;
    j["verified"] = verified;
    j["plan"] = nlohmann::json::array();
    for (const auto& s : best.steps) j["plan"].push_back(agents::planner::to_string(s, world));
    if (!best.found()) j["why"] = best.why;
    if (!replayed.is_null()) j["replay"] = replayed;
    std::cout << j.dump() << std::endl;
  } else {
    if (best.found()) {
      for (const auto& s : best.steps) std::cout << agents::planner::to_string(s, world) << "\n";
      std::cout << "# cost: " << best.cost;
      if (best.search_cost != best.cost) std::cout << " (" << best.search_cost << " as searched, before decomposition)";
      std::cout << ", " << best.steps.size() << " steps, " << best.expansions << " expansions, " << best.generated
                << " states generated, " << best.searches << " searches, " << std::fixed << std::setprecision(4)
                << median << " s\n";
      std::cout << "# verified through the grammar guard: " << verified << "\n";
    } else {
      std::cout << "# no plan (" << agents::planner::to_string(best.outcome) << "): " << best.why << "\n";
      std::cout << "# " << best.expansions << " expansions, " << median << " s\n";
    }
    if (!replayed.is_null()) {
      std::cout << "# replay of " << a.replay << ":\n";
      for (const auto& st : replayed["steps"])
        std::cout << "#   " << st["step"].get<std::string>() << ": " << st["verdict"].get<std::string>() << "\n";
      std::cout << "#   " << (replayed["reaches_mission"].get<bool>() ? "reaches the mission" : "does not reach the mission")
                << "\n";
    }
    for (const std::string& n : domain->notes()) std::cout << "# note: " << n << "\n";
  }
  if (!best.found())
    set_exit_code(1);
  else if (a.verify && verified != "ok")
    set_exit_code(3);
}

struct BenchArgs {
  std::vector<std::string> problems;  // GRAMMAR:WORLD:MISSION
  int runs = 5;
  std::vector<std::string> include_dirs;
};

// One JSON line per problem: the median, min and max time of `runs` plans.
void run_bench(const BenchArgs& a) {
  std::vector<std::string> problems = a.problems;
  for (const std::string& spec : problems) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
      const auto c = spec.find(':', start);
      parts.push_back(spec.substr(start, c - start));
      if (c == std::string::npos) break;
      start = c + 1;
    }
    if (parts.size() != 3) {
      std::cerr << "error: '" << spec << "': expected GRAMMAR:WORLD:MISSION\n";
      set_exit_code(2);
      return;
    }
    auto p = load_problem(parts[0], parts[1], parts[2], a.include_dirs);
    if (!p.ok()) {
      std::cerr << "error: " << p.error().message << "\n";
      set_exit_code(2);
      return;
    }
    std::vector<double> times;
    PlanResult r;
    for (int i = 0; i < a.runs; ++i) {
      const std::int64_t t0 = steady_ns();
      auto world = agents::symbolic::read_world(*p->graph, p->grammar.types);
      agents::planner::Domain d(p->grammar, world.vocabulary);
      auto cm = agents::compile_mission(p->mission, world);
      if (!cm.ok()) break;
      r = agents::planner::plan(d, world.state, *cm);
      times.push_back((steady_ns() - t0) / 1e9);
    }
    std::sort(times.begin(), times.end());
    nlohmann::json j;
    j["bench"] = "planner";
    j["problem"] = spec;
    j["outcome"] = agents::planner::to_string(r.outcome);
    j["cost"] = r.cost;
    j["length"] = r.steps.size();
    j["expansions"] = r.expansions;
    if (!times.empty()) {
      j["median_s"] = times[times.size() / 2];
      j["min_s"] = times.front();
      j["max_s"] = times.back();
      j["runs"] = times.size();
    }
    std::cout << j.dump() << std::endl;
  }
}

}  // namespace

void add_planner_commands(CLI::App& app) {
  auto* mission = app.add_subcommand("mission", "Missions: AGM's .aggt targets (docs/planner.md)");
  auto ma = std::make_shared<MissionArgs>();
  auto* check = mission->add_subcommand(
      "check", "Does the world hold the mission? Exit 0 if it does, 1 if not (printing what is missing), 2 on error");
  check->add_option("world", ma->world, "world file: Quiver JSON, AGM XML or CORTEX JSON")
      ->required()
      ->check(CLI::ExistingFile);
  check->add_option("mission", ma->mission, "mission file: an AGM target (.aggt, or AGM XML: an <AGMModel> pattern)")->required()->check(CLI::ExistingFile);
  check->add_option("--domain", ma->domain, "domain grammar (.aggl), for type inheritance")->check(CLI::ExistingFile);
  check->add_option("-I,--include-dir", ma->include_dirs, "where the domain's include(...) files are looked for")
      ->allow_extra_args(false)
      ->check(CLI::ExistingDirectory);
  check->add_flag("--json", ma->json, "one JSON line");
  check->add_option("--schema", ma->schema,
                    "the shared vocabulary (docs/schema.md): exit 2 if the mission (or --domain) uses what it does not declare")
      ->check(CLI::ExistingFile);
  check->callback([ma] { run_mission_check(*ma); });

  auto pa = std::make_shared<PlanArgs>();
  auto* plan = app.add_subcommand("plan",
                                  "Find the cheapest sequence of active rules from a world to a mission "
                                  "(A*; exit 0 with a plan, 1 without, 3 if the plan failed verification)");
  plan->add_option("grammar", pa->grammar, "domain grammar (.aggl)")->required()->check(CLI::ExistingFile);
  plan->add_option("world", pa->world, "world file: Quiver JSON, AGM XML or CORTEX JSON")
      ->required()
      ->check(CLI::ExistingFile);
  plan->add_option("mission", pa->mission, "mission file: an AGM target (.aggt, or AGM XML: an <AGMModel> pattern)")->required()->check(CLI::ExistingFile);
  plan->add_option("-I,--include-dir", pa->include_dirs, "where the grammar's include(...) files are looked for")
      ->allow_extra_args(false)
      ->check(CLI::ExistingDirectory);
  plan->add_option("--max-time", pa->max_time_s, "give up after this many seconds (0: no limit)")
      ->check(CLI::Range(0.0, 1e7))
      ->capture_default_str();
  plan->add_option("--max-expansions", pa->max_expansions, "give up after this many expansions (0: no limit)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1'000'000'000'000}))
      ->capture_default_str();
  plan->add_option("--max-world-increment", pa->max_world_increment,
                   "a state may hold at most this many nodes more than the world (AGM's maxWorldIncrement)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  plan->add_flag("--verify,!--no-verify", pa->verify,
                 "replay the plan on the world through the grammar guard (default on)")
      ->capture_default_str();
  plan->add_flag("--no-heuristic", pa->no_heuristic, "uniform-cost search (h = 0), to compare");
  plan->add_option("--runs", pa->runs, "plan this many times and report the median time")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  plan->add_option("--replay", pa->replay,
                   "also replay another planner's plan (AGM's .plan: one rule@{...} per line) with Quiver's "
                   "meaning of the rules, and tell whether it reaches the mission")
      ->check(CLI::ExistingFile);
  plan->add_flag("--json", pa->json, "one JSON line");
  plan->add_option("--schema", pa->schema,
                   "the shared vocabulary (docs/schema.md): exit 2 if the mission or the grammar uses what it does not declare")
      ->check(CLI::ExistingFile);
  plan->callback([pa] { run_plan(*pa); });

  CLI::App* bench = app.get_subcommand("bench");
  auto ba = std::make_shared<BenchArgs>();
  auto* pb = bench->add_subcommand("planner", "Planner: median time of several plans per problem");
  pb->add_option("problems", ba->problems, "GRAMMAR:WORLD:MISSION, one or more")->required();
  pb->add_option("--runs", ba->runs)->check(CLI::Range(1, 1000))->capture_default_str();
  pb->add_option("-I,--include-dir", ba->include_dirs)->allow_extra_args(false)->check(CLI::ExistingDirectory);
  pb->callback([ba] { run_bench(*ba); });
}

}  // namespace quiver::tools
