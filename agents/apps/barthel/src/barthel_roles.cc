// The Barthel agents by role name: each made with its devices (real ones writing into out_dir, else simulated),
// and given the other roles' grammars, against which their changes are verified.
#include "quiver/agents/apps/barthel/barthel_roles.h"

#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/patient.h"
#include "quiver/agents/devices/espeak_speech_output.h"
#include "quiver/agents/devices/file_pager.h"
#include "quiver/agents/devices/json_result_store.h"
#include "quiver/agents/devices/memory_pager.h"
#include "quiver/agents/devices/memory_result_store.h"
#include "quiver/agents/devices/opencv_screen.h"
#include "quiver/agents/devices/simulated_screen.h"
#include "quiver/agents/devices/simulated_speech_output.h"

namespace quiver::agents::inline apps::barthel {

const std::vector<std::string>& role_names() {
  static const std::vector<std::string> kRoles = {"planner", "speech", "panel", "person", "patient"};
  return kRoles;
}

namespace {

Result<std::unique_ptr<Agent>> make_agent(std::string_view role, const RoleOptions& o) {
  const bool real = !o.out_dir.empty();
  auto name = [&](std::string_view fallback) { return o.name.empty() ? std::string(fallback) : o.name; };
  if (role == "planner") {
    if (o.store && o.pager) return std::unique_ptr<Agent>(std::make_unique<Planner>(*o.store, *o.pager, o.planner, name(role)));
    std::unique_ptr<devices::ResultStore> store;
    std::unique_ptr<devices::Pager> pager;
    if (real) {
      store = std::make_unique<devices::JsonResultStore>(o.out_dir + "/result.json");
      pager = std::make_unique<devices::FilePager>(o.out_dir + "/pages.jsonl");
    } else {
      store = std::make_unique<devices::MemoryResultStore>();
      pager = std::make_unique<devices::MemoryPager>();
    }
    return std::unique_ptr<Agent>(std::make_unique<Planner>(std::move(store), std::move(pager), o.planner, name(role)));
  }
  if (role == "speech") {
    std::unique_ptr<devices::SpeechOutput> out;
    if (real && !o.simulated_speech) out = std::make_unique<devices::EspeakSpeechOutput>(o.out_dir + "/speech");
    else out = std::make_unique<devices::SimulatedSpeechOutput>(o.sim_ns_per_word, o.sim_base_ns);
    return std::unique_ptr<Agent>(
        std::make_unique<Speech>(std::move(out), simulated_speech_input(o.truth), o.speech, name(role)));
  }
  if (role == "panel") {
    std::unique_ptr<devices::Screen> screen;
    if (real) screen = std::make_unique<devices::OpenCvScreen>(o.out_dir + "/screen");
    else screen = std::make_unique<devices::SimulatedScreen>();
    return std::unique_ptr<Agent>(
        std::make_unique<Panel>(std::move(screen), simulated_touch_input(o.truth), o.panel, name(role)));
  }
  if (role == "person")
    return std::unique_ptr<Agent>(std::make_unique<Person>(simulated_person_sensor(o.truth), o.person, name(role)));
  if (role == "patient") return std::unique_ptr<Agent>(std::make_unique<Patient>(o.script, name(role)));
  std::string known;
  for (const auto& r : role_names()) known += (known.empty() ? "" : ", ") + r;
  return make_error(ErrorCode::kInvalidArgument, "unknown role '" + std::string(role) + "' (roles: " + known + ")");
}

}  // namespace

Result<std::unique_ptr<Agent>> make_role(std::string_view role, const RoleOptions& o) {
  auto a = make_agent(role, o);
  if (!a.ok()) return a;
  // Each agent's changes arrive claiming a rule of that agent's own grammar.
  for (const auto& other : role_names())
    if (other != role && !role_grammar(other).empty())
      (*a)->add_peer_grammar(other, std::string(role_grammar(other)), other + ".aggl");
  return a;
}

}  // namespace quiver::agents::inline apps::barthel
