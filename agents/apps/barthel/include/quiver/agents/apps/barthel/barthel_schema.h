#pragma once
/// @file
/// The world model of the Barthel test (seed 000, §III-IV) as the agents share it: the names of
/// its nodes, edges and attributes, and the reads every agent makes. The agents never talk to one
/// another; everything below is what they read and write.
///
/// Nodes (examples/barthel/world.json): world, robot, speaker, panel, test, clinician, person (with
/// its body: 15 joints as RT children of `body`), and `sim_patient` (the simulated patient's ground
/// truth, read only by simulated devices).
///
/// - `person -[in_front_of]-> robot`: the person sits in front of the robot (Person writes it;
///   `person.seen_ns` and `person.present` are the sensor's last reading, at its rate).
/// - `test -[say]-> u:utterance`: the Planner wants `u` said (attributes of `u`: text, purpose,
///   item, attempt, seq, options, and what the screen shows with it: title, screen_text, buttons).
/// - `speaker -[speaking]-> u` while Speech says it; `speaker -[spoke]-> u` once it has been said
///   to the end (an interrupted utterance goes back to neither).
/// - `panel -[showing]-> u` while the Panel shows u's screen; the picture the screen shows is the
///   image `screen` on `panel` (kScreenImage; docs/images.md), when the screen renders pictures.
/// - `speaker -[heard]-> u` / `panel -[tapped]-> u`: the patient's answer to question u (edge
///   attributes `option` (index, -1 when not understood) and `text`).
/// - `test -[calls]-> clinician`: the clinician was paged.
/// - The test's progress is attributes of `test` (the Planner's state: a restarted or second
///   Planner continues from them): status, item, attempt, phase, current, deadline_ns,
///   remaining_ns, unanswered, absent, answers (JSON), seq.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/graph/graph.h"

namespace quiver::agents::inline apps::barthel {

namespace node {
inline constexpr std::string_view kRobot = "robot";
inline constexpr std::string_view kSpeaker = "speaker";
inline constexpr std::string_view kPanel = "panel";
inline constexpr std::string_view kTest = "test";
inline constexpr std::string_view kPerson = "person";
inline constexpr std::string_view kBody = "body";
inline constexpr std::string_view kClinician = "clinician";
inline constexpr std::string_view kSimPatient = "sim_patient";
}  // namespace node

namespace edge {
inline constexpr std::string_view kInFrontOf = "in_front_of";
inline constexpr std::string_view kSay = "say";
inline constexpr std::string_view kSpeaking = "speaking";
inline constexpr std::string_view kSpoke = "spoke";
inline constexpr std::string_view kShowing = "showing";
inline constexpr std::string_view kHeard = "heard";
inline constexpr std::string_view kTapped = "tapped";
inline constexpr std::string_view kCalls = "calls";
}  // namespace edge

/// The image prefix of the picture the panel's screen shows: attributes `screen`,
/// `screen_width`, `screen_height`, `screen_encoding` of `panel` (agents/view/images/image_attrs.h).
inline constexpr std::string_view kScreenImage = "screen";

/// The 15 body joints the person sensor tracks (the AGM paper's human model).
const std::vector<std::string>& joint_names();

/// What the Planner asks for. `purpose`: intro | question | retry | call_back | welcome_back |
/// goodbye | clinician.
struct Prompt {
  graph::NodeId id;
  std::int64_t seq = 0;
  std::string text;
  std::string purpose;
  int item = -1;    ///< index into barthel_items(), -1 for none
  int attempt = 0;  ///< 1 or 2 for questions
  std::string title, screen_text;
  std::vector<std::string> options;  ///< the answers it admits (said and recognised)
  bool buttons = false;              ///< the screen shows the options as buttons to touch
  bool is_question() const { return purpose == "question" || purpose == "retry"; }
  bool has_screen() const { return !title.empty() || !screen_text.empty(); }
};

/// An answer to a prompt: by voice (`heard`) or touch (`tapped`).
struct Answer {
  int option = -1;  ///< -1: not understood
  std::string text;
  std::string channel;  ///< "voice" | "touch"
};

/// The node of that name, or the null id.
graph::NodeId node_id(const graph::Graph& g, std::string_view name);
/// True while `person -[in_front_of]-> robot` exists.
bool person_present(const graph::Graph& g);
/// May the robot address the patient now? The edge says someone sits there, and the sensor's
/// latest reading (person.seen_ns, person.present: written together with every reading, so any
/// reading that arrives carries the presence even when the edge's change is still missing) is
/// at most `stale_ns` old and says present.
bool patient_in_front(const graph::Graph& g, std::int64_t now_ns, std::int64_t stale_ns);
/// The person sensor's last reading time (person.seen_ns), 0 if none.
std::int64_t person_seen_ns(const graph::Graph& g);
/// Every prompt of the test, by seq (then id).
std::vector<Prompt> prompts(const graph::Graph& g);
/// The same order, only the ids: cheap to scan (each agent does every round); prompt_at() reads
/// the one it wants.
std::vector<graph::NodeId> prompt_ids(const graph::Graph& g);
/// The prompt at node `u` (nullopt when `u` is not an utterance).
std::optional<Prompt> prompt_at(const graph::Graph& g, graph::NodeId u);
/// The prompt with this seq (the first by id if a partition made two), or nullopt.
std::optional<Prompt> prompt_by_seq(const graph::Graph& g, std::int64_t seq);
/// `from -[type]-> u` exists for the node of name `from`.
bool marked(const graph::Graph& g, std::string_view from, std::string_view type, graph::NodeId u);
/// The answer given to `u` (voice first), if any.
std::optional<Answer> answer_to(const graph::Graph& g, graph::NodeId u);

/// Takes a mark back: deletes `from -[type]-> to`, or every `from -[type]->` edge when `to` is
/// null, one commit per edge (each is one rule application). Missing edges are no error.
Status take_back(graph::Graph& g, std::string_view from, std::string_view type, graph::NodeId to = {});

/// Attribute readers that give `fallback` when the attribute is missing or of another type.
/// The Symbol forms save interning the name on paths that read many attributes (prompts).
std::string attr_string(const graph::Graph& g, graph::NodeId n, graph::Symbol name, std::string fallback = {});
std::int64_t attr_int(const graph::Graph& g, graph::NodeId n, graph::Symbol name, std::int64_t fallback = 0);
bool attr_bool(const graph::Graph& g, graph::NodeId n, graph::Symbol name, bool fallback = false);
inline std::string attr_string(const graph::Graph& g, graph::NodeId n, std::string_view name,
                               std::string fallback = {}) {
  return attr_string(g, n, graph::Symbol(name), std::move(fallback));
}
inline std::int64_t attr_int(const graph::Graph& g, graph::NodeId n, std::string_view name, std::int64_t fallback = 0) {
  return attr_int(g, n, graph::Symbol(name), fallback);
}
inline bool attr_bool(const graph::Graph& g, graph::NodeId n, std::string_view name, bool fallback = false) {
  return attr_bool(g, n, graph::Symbol(name), fallback);
}

/// Options travel as one string attribute, one per line.
std::string join_lines(const std::vector<std::string>& lines);
std::vector<std::string> split_lines(std::string_view text);

}  // namespace quiver::agents::inline apps::barthel
