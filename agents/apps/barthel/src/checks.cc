// What a Barthel run is checked against in either host: the stored result against the patient's script, no
// question asked twice, and how long the robot spoke to an absent patient.
#include "quiver/agents/apps/barthel/checks.h"

#include <algorithm>
#include <map>
#include <optional>

#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/apps/barthel/items.h"

namespace quiver::agents::inline apps::barthel {
namespace {
std::string score_text(const std::optional<int>& s) { return s ? std::to_string(*s) : "none"; }
}  // namespace

std::vector<std::string> result_differences(const devices::TestResult& r, const PatientScript::Outcome& expected) {
  std::vector<std::string> out;
  if (r.status != expected.status) out.push_back("status " + r.status + " but the script implies " + expected.status);
  if (r.total != expected.total)
    out.push_back("total " + std::to_string(r.total) + " but the script implies " + std::to_string(expected.total));
  const auto& items = barthel_items();
  std::map<std::string, std::optional<int>> got;
  for (const auto& ir : r.items) got[ir.item] = ir.score;
  for (std::size_t i = 0; i < expected.scores.size() && i < items.size(); ++i) {
    auto it = got.find(items[i].id);
    if (it == got.end())
      out.push_back("item " + items[i].id + " missing from the result (skipped)");
    else if (it->second != expected.scores[i])
      out.push_back("item " + items[i].id + ": score " + score_text(it->second) + ", the script implies " +
                    score_text(expected.scores[i]));
  }
  if (r.items.size() != expected.scores.size())
    out.push_back(std::to_string(r.items.size()) + " items in the result, the script implies " +
                  std::to_string(expected.scores.size()));
  return out;
}

std::vector<std::string> questions_asked_twice(const graph::Graph& g) {
  std::map<std::pair<int, int>, int> said;
  for (const auto& p : prompts(g))
    if (p.is_question() && marked(g, node::kSpeaker, edge::kSpoke, p.id)) ++said[{p.item, p.attempt}];
  std::vector<std::string> out;
  for (const auto& [k, n] : said)
    if (n > 1)
      out.push_back("item " + std::to_string(k.first) + " attempt " + std::to_string(k.second) + " asked " +
                    std::to_string(n) + " times");
  return out;
}

bool patient_present_truth(const graph::Graph& g) {
  return attr_bool(g, node_id(g, node::kSimPatient), "present", true);
}

bool speaking_to_patient(const graph::Graph& g) {
  const graph::NodeId sp = node_id(g, node::kSpeaker);
  if (sp.is_null()) return false;
  for (const graph::EdgeKey& e : g.edges_from(sp, graph::Symbol(edge::kSpeaking))) {
    auto p = prompt_at(g, e.to);
    if (p && p->purpose != "call_back") return true;
  }
  return false;
}

void AbsenceWatch::sample(std::int64_t now, bool present, bool speaking) {
  if (present) {
    absent_since_ = -1;
    return;
  }
  if (absent_since_ < 0) absent_since_ = now;
  if (speaking) max_ms_ = std::max(max_ms_, static_cast<double>(now - absent_since_) / 1e6);
}

}  // namespace quiver::agents::inline apps::barthel
