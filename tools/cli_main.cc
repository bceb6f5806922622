// What every quiver executable shares (quiver, quiver-agent, quiver-barthel): the global options,
// the message for a missing or unknown command word, and parsing (commands.h).
#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"

namespace quiver::tools {
namespace {

// The commands under `a` (CLI11 keeps option groups as subcommands too).
std::vector<CLI::App*> commands_of(CLI::App* a) {
  return a->get_subcommands([](CLI::App* s) { return dynamic_cast<CLI::Option_group*>(s) == nullptr; });
}

// A command made only of subcommands says which word it did not know, and lists the ones it
// does, instead of CLI11's "A subcommand is required".
void require_known_subcommand(CLI::App* a, const std::string& path) {
  auto word = std::make_shared<std::string>();
  a->require_subcommand(0, 1);
  a->add_option("command", *word)->group("");  // hidden: catches a word that is no subcommand
  a->callback([a, path, word] {
    if (!a->get_subcommands().empty()) return;
    std::string known;
    for (const CLI::App* s : commands_of(a))
      if (!s->get_group().empty()) known += (known.empty() ? "" : ", ") + s->get_name();
    const std::string what = word->empty() ? path + ": which command? (" : path + ": unknown command '" + *word + "' (";
    throw CLI::ParseError(what + "the commands are: " + known + "; " + path + " --help tells more)", CLI::ExitCodes::ExtrasError);
  });
}

}  // namespace

void add_global_options(CLI::App& app, const std::string& program) {
  app.set_version_flag("--version", program + " " + QUIVER_VERSION);
  app.add_option_function<std::string>(
         "--log-level",
         [](const std::string& level) {
           if (!agents::set_log_level(level))
             throw CLI::ValidationError("--log-level", "'" + level + "' is none of trace, debug, info, warn, error, critical, off");
         },
         "messages at least this severe are logged to stderr (default info)")
      ->envname("QUIVER_LOG_LEVEL");
}

void require_known_subcommands(CLI::App& app, const std::string& program) {
  require_known_subcommand(&app, program);
  for (CLI::App* sub : commands_of(&app))
    if (!commands_of(sub).empty()) require_known_subcommand(sub, program + " " + sub->get_name());
}

int run_cli(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return exit_code();
}

}  // namespace quiver::tools
