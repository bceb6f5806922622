// quiver keys init | add-agent | revoke | list: the credentials of DDS Security (docs/security.md).

#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/replica/security/keys.h"

namespace quiver::tools {
namespace {

namespace security = agents::security;

struct KeysArgs {
  std::string dir;
  std::string name;
  security::AgentKeyOptions agent;
};

// Exit status: 0 done, 1 refused (exists, unknown agent, bad name), 2 failed (I/O, OpenSSL).
void finish(const char* what, const Status& s) {
  if (s.ok()) {
    set_exit_code(0);
    return;
  }
  agents::named_logger("quiver keys")->error("{}: {}", what, s.error().to_string());
  const ErrorCode c = s.error().code;
  set_exit_code(c == ErrorCode::kIo || c == ErrorCode::kInternal ? 2 : 1);
}

void run_list(const std::string& dir) {
  auto agents = security::list_agents(dir);
  if (!agents.ok()) {
    finish("list", agents.error());
    return;
  }
  for (const security::AgentInfo& a : *agents) {
    std::cout << a.name << "  "
              << (a.valid     ? "valid"
                  : a.revoked ? "REVOKED"
                  : a.expired ? "EXPIRED"
                              : "INVALID");
    if (!a.not_before.empty()) std::cout << "  " << a.not_before << " .. " << a.not_after;
    if (!a.serial.empty()) std::cout << "  serial " << a.serial;
    if (!a.valid && !a.revoked && !a.expired && !a.problem.empty())
      std::cout << "  (" << a.problem << ")";
    std::cout << "\n";
  }
  std::cout << agents->size() << " agent" << (agents->size() == 1 ? "" : "s") << " in " << dir
            << std::endl;
  set_exit_code(0);
}

}  // namespace

void add_keys_commands(CLI::App& app) {
  auto* keys =
      app.add_subcommand("keys",
                         "DDS Security credentials: a CA, agent certificates and permissions "
                         "(docs/security.md)");
  auto args = std::make_shared<KeysArgs>();

  auto* init = keys->add_subcommand("init",
                                    "Create a CA, the governance document and an empty CRL in DIR "
                                    "(never overwrites a CA)");
  init->add_option("dir", args->dir, "the credentials directory (created if missing)")->required();
  init->callback([args] {
    finish("init", security::init_keys(args->dir, {}));
    if (exit_code() == 0) std::cout << "CA created in " << args->dir << std::endl;
  });

  auto* add =
      keys->add_subcommand("add-agent",
                           "Create agent NAME's key, certificate and permissions, signed by "
                           "the CA in DIR");
  add->add_option("name", args->name, "agent name ([A-Za-z0-9_.-], at most 64 characters)")
      ->required();
  add->add_option("--dir", args->dir, "the credentials directory")->required();
  add->add_option("--valid-days", args->agent.valid_days, "the certificate's lifetime in days")
      ->check(CLI::Range(1e-6, 36500.0))
      ->capture_default_str();
  add->add_option(
         "--backdate-days", args->agent.backdate_days,
         "testing: the certificate starts this many days ago (an expired one: --backdate-days 2 "
         "--valid-days 1)")
      ->check(CLI::Range(0.0, 36500.0));
  add->callback([args] {
    finish("add-agent", security::add_agent(args->dir, args->name, args->agent));
    if (exit_code() == 0)
      std::cout << "agent " << args->name << ": credentials in " << args->dir << "/agents/"
                << args->name << std::endl;
  });

  auto* revoke =
      keys->add_subcommand("revoke", "Revoke agent NAME's certificate (adds it to DIR/crl.pem)");
  revoke->add_option("name", args->name, "agent name")->required();
  revoke->add_option("--dir", args->dir, "the credentials directory")->required();
  revoke->callback([args] {
    finish("revoke", security::revoke_agent(args->dir, args->name));
    if (exit_code() == 0)
      std::cout << "agent " << args->name << " revoked: copy " << args->dir
                << "/crl.pem to every host; peers refuse it from their next start" << std::endl;
  });

  auto* list = keys->add_subcommand("list", "The agents in DIR: validity, revoked or not");
  list->add_option("--dir", args->dir, "the credentials directory")->required();
  list->callback([args] { run_list(args->dir); });
}

}  // namespace quiver::tools
