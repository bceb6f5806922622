// Every numeric option of every `quiver` subcommand is range-checked: a negative number (where
// the option does not mean one), zero where nothing can be done with it, and absurdly large
// values are refused while parsing, with a message naming the option; nothing runs.

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <set>
#include <string>
#include <vector>

#include "commands.h"

namespace quiver::tools {
namespace {

struct Numeric {
  std::vector<std::string> path;  // subcommand names
  std::string flag;               // "--nodes"
  std::string type;               // CLI11's type name: INT, UINT, FLOAT, ...
  std::string good;               // a value it takes (its default, else 1)
};

// What a subcommand needs besides the option under test, so that a refusal is the option's.
std::vector<std::string> required(const std::vector<std::string>& path) {
  if (path == std::vector<std::string>{"agent"}) return {"--name", "a"};
  if (path == std::vector<std::string>{"lookup"}) return {"/dev/null", "a", "b"};
  if (path == std::vector<std::string>{"import-urdf"}) return {"/dev/null", "-o", "/dev/null"};
  for (const char* c : {"import-dsr", "import-agm", "export-dsr", "export-agm"})
    if (path == std::vector<std::string>{c}) return {"/dev/null", "-o", "/dev/null"};
  if (path == std::vector<std::string>{"bench-dds-role"}) return {"writer"};
  if (path == std::vector<std::string>{"run"}) return {"planner"};
  if (path == std::vector<std::string>{"record"}) return {"-o", "/dev/null"};
  if (path == std::vector<std::string>{"render"}) return {"world.json", "-o", "x.png"};
  if (path == std::vector<std::string>{"timeline"}) return {"run.qrec", "-o", "x.mp4"};
  if (path == std::vector<std::string>{"plan"}) return {"/dev/null", "/dev/null", "/dev/null"};
  if (path == std::vector<std::string>{"mission", "check"}) return {"/dev/null", "/dev/null"};
  if (path == std::vector<std::string>{"bench", "planner"}) return {"d.aggl:w.xml:m.aggt"};
  if (path == std::vector<std::string>{"keys", "add-agent"}) return {"a", "--dir", "/nonexistent"};
  if (path == std::vector<std::string>{"gateway"}) return {"--robot", "A", "--team", "/dev/null"};
  if (path == std::vector<std::string>{"launch"}) return {"/dev/null"};
  return {};
}

void collect(CLI::App* app, std::vector<std::string> path, std::vector<Numeric>& out) {
  for (CLI::Option* o : app->get_options()) {
    const std::string t = o->get_type_name();
    const bool numeric = t.rfind("INT", 0) == 0 || t.rfind("UINT", 0) == 0 || t.rfind("FLOAT", 0) == 0 ||
                         t.find("INT") != std::string::npos || t.find("FLOAT") != std::string::npos;
    if (!numeric || o->get_lnames().empty()) continue;
    out.push_back(Numeric{path, "--" + o->get_lnames()[0], t, o->get_default_str()});
  }
  for (CLI::App* sub : app->get_subcommands([](CLI::App*) { return true; })) {
    auto p = path;
    p.push_back(sub->get_name());
    collect(sub, p, out);
  }
}

// Parses `args`; the commands do not run (the app's parse-complete callback, which CLI11 calls
// after every check and before any command, stops there).
struct Parsed {};
std::string parse_error(const std::vector<std::string>& args) {
  CLI::App app;
  build_app(app);
  app.parse_complete_callback([] { throw Parsed{}; });
  std::vector<std::string> argv(args.rbegin(), args.rend());  // CLI11 takes them reversed
  try {
    app.parse(argv);
  } catch (const CLI::ParseError& e) {
    return e.what();
  } catch (const Parsed&) {
  }
  return "";
}

// Options that may be negative by meaning (a time in the RT stamps' unit).
const std::set<std::string> kSigned = {"lookup --at"};

std::string name(const Numeric& n) {
  std::string s;
  for (const auto& p : n.path) s += p + " ";
  return s + n.flag;
}

TEST(CliOptionsTest, EveryNumericOptionRefusesANegativeNumber) {
  CLI::App app;
  build_app(app);
  std::vector<Numeric> all;
  collect(&app, {}, all);
  ASSERT_GT(all.size(), 20u) << "the walk found the options";
  int checked = 0;
  for (const Numeric& n : all) {
    std::vector<std::string> args = n.path;
    for (const auto& r : required(n.path)) args.push_back(r);
    // The control: some ordinary value parses (its default, else a small number).
    bool control = false;
    for (std::string v : {n.good, std::string("1"), std::string("0"), std::string("2")}) {
      if (v.empty() || v.find_first_of(" [,") != std::string::npos) continue;
      args.push_back(n.flag + "=" + v);
      control = parse_error(args).empty();
      if (control) break;
      args.pop_back();
    }
    ASSERT_TRUE(control) << name(n) << " takes none of its default, 0, 1 or 2 (the control)";
    if (kSigned.count(name(n))) continue;
    args.back() = n.flag + "=-1";  // "=": a bare -1 could parse as an unknown flag
    std::string err = parse_error(args);
    EXPECT_FALSE(err.empty()) << name(n) << " accepts -1";
    EXPECT_NE(err.find(n.flag), std::string::npos) << name(n) << ": the message names the option: " << err;
    ++checked;
  }
  std::printf("[cli] %d numeric options refuse -1\n", checked);
}

TEST(CliOptionsTest, EveryNumericOptionRefusesAnAbsurdlyLargeNumber) {
  CLI::App app;
  build_app(app);
  std::vector<Numeric> all;
  collect(&app, {}, all);
  for (const Numeric& n : all) {
    std::vector<std::string> args = n.path;
    for (const auto& r : required(n.path)) args.push_back(r);
    args.push_back(n.flag + "=1e300");
    EXPECT_FALSE(parse_error(args).empty()) << name(n) << " accepts 1e300";
  }
}

// The cases the issue found, by hand: each used to crash, hang or lie.
TEST(CliOptionsTest, TheReportedCasesAreRefused) {
  for (const auto& args : std::vector<std::vector<std::string>>{{"bench", "grammar", "--nodes=-5"},
                                                                {"bench", "scene", "--objects=0"},
                                                                {"bench", "dds", "--updates=-5"},
                                                                {"bench", "dds", "--updates=0"},
                                                                {"sim", "--seed=-1"},
                                                                {"agent", "--name", "a", "--run-for=-1"},
                                                                {"bench", "locks", "--rounds=0"},
                                                                {"dump", "--timeout=0"}}) {
    std::string err = parse_error(args);
    const std::string flag = args.back().substr(0, args.back().find('='));
    EXPECT_FALSE(err.empty()) << args.back();
    EXPECT_NE(err.find(flag), std::string::npos) << "the message names the option: " << err;
  }
}

TEST(CliOptionsTest, GoodValuesStillParse) {
  EXPECT_EQ(parse_error({"sim", "--seed", "7", "--agents", "3"}), "");
  EXPECT_EQ(parse_error({"bench", "crdt", "--nodes", "10", "--updates", "100"}), "");
  EXPECT_EQ(parse_error({"lookup", "/dev/null", "a", "b", "--at=-5"}), "");
}

}  // namespace
}  // namespace quiver::tools
