// The simulated patient agent: it answers what was said to the end as its script says, leaves its chair and
// comes back, and writes only the `sim_patient` node the simulated sensors read.
#include "quiver/agents/apps/barthel/patient.h"

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/apps/barthel/items.h"

namespace quiver::agents::inline apps::barthel {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

Patient::Patient(PatientScript script, std::string name) : Agent(std::move(name)), script_(std::move(script)) {
  set_grammar_text(std::string(role_grammar("patient")), "patient.aggl");
}

void Patient::setup(AgentContext& ctx) {
  // A restarted simulation continues: what was answered is in the truth node.
  const graph::Graph& g = ctx.graph();
  NodeId me = node_id(g, node::kSimPatient);
  answered_seq_ = std::max(attr_int(g, me, "said_for", 0), attr_int(g, me, "tap_for", 0));
  answered_seq_ = std::max(answered_seq_, attr_int(g, me, "answered", 0));
  if (!attr_bool(g, me, "present", true)) back_at_ = ctx.now();
}

Status Patient::write(AgentContext& ctx, std::vector<std::pair<std::string, Value>> attrs) {
  graph::Graph& g = ctx.graph();
  NodeId me = node_id(g, node::kSimPatient);
  if (me.is_null()) return make_error(ErrorCode::kNotFound, "patient: no sim_patient node in the world");
  graph::Transaction tx = g.begin();
  for (auto& [k, v] : attrs)
    if (Status s = tx.set(me, k, std::move(v)); !s.ok()) return s;
  auto c = tx.commit();
  return c.ok() ? Status{} : Status(c.error());
}

void Patient::on_tick(AgentContext& ctx) {
  const graph::Graph& g = ctx.graph();
  const std::int64_t now = ctx.now();
  NodeId me = node_id(g, node::kSimPatient);
  if (me.is_null()) return;
  const bool present = attr_bool(g, me, "present", true);

  // Leaving mid-sentence: the first question of the scripted item is being said.
  if (present && back_at_ < 0 && next_leave_ < script_.leaves.size()) {
    const Leave& l = script_.leaves[next_leave_];
    NodeId speaker = node_id(g, node::kSpeaker);
    if (leave_at_ < 0) {
      for (const graph::EdgeKey& e : g.edges_from(speaker, Symbol(edge::kSpeaking))) {
        auto p = prompt_at(g, e.to);
        if (p && p->purpose == "question" && p->item == l.item) leave_at_ = now + l.after_ns;
      }
    } else if (now >= leave_at_) {
      if (write(ctx, {{"present", Value(false)}}).ok()) {
        ctx.log("leaves the chair");
        back_at_ = now + l.for_ns;
        leave_at_ = -1;
        ++next_leave_;
        ++leaves_;
      }
      return;
    }
  }
  if (!present) {
    if (back_at_ >= 0 && now >= back_at_ && write(ctx, {{"present", Value(true)}}).ok()) {
      ctx.log("sits down again");
      back_at_ = -1;
    }
    return;
  }

  // The newest question said to the end, not answered yet.
  std::optional<Prompt> q;
  const auto ids = prompt_ids(g);
  for (auto it = ids.rbegin(); it != ids.rend() && !q; ++it)
    if (marked(g, node::kSpeaker, edge::kSpoke, *it))
      if (auto p = prompt_at(g, *it); p && p->is_question()) q = std::move(p);
  if (!q || q->seq <= answered_seq_) return;
  if (pending_seq_ != q->seq) {
    pending_seq_ = q->seq;
    const auto span = static_cast<std::uint64_t>(script_.think_max_ns - script_.think_min_ns + 1);
    answer_at_ = now + script_.think_min_ns + static_cast<std::int64_t>(ctx.rng().below(span));
    return;
  }
  if (now < answer_at_) return;
  if (q->item < 0 || static_cast<std::size_t>(q->item) >= script_.items.size()) return;
  const ItemPlan& plan = script_.items[static_cast<std::size_t>(q->item)];
  const Reply& r = q->attempt <= 1 ? plan.first : plan.second;
  const auto& options = barthel_items()[static_cast<std::size_t>(q->item)].options;
  Status s;
  switch (r.kind) {
    case ReplyKind::kVoice:
      s = write(ctx, {{"said_seq", Value(attr_int(g, me, "said_seq") + 1)},
                      {"said_text", Value("I would say: " + options[static_cast<std::size_t>(r.option)].label)},
                      {"said_for", Value(q->seq)}, {"answered", Value(q->seq)}});
      break;
    case ReplyKind::kTouch:
      s = write(ctx, {{"tap_seq", Value(attr_int(g, me, "tap_seq") + 1)},
                      {"tap_option", Value(static_cast<std::int64_t>(r.option))},
                      {"tap_for", Value(q->seq)}, {"answered", Value(q->seq)}});
      break;
    case ReplyKind::kMisunderstand:
      s = write(ctx, {{"said_seq", Value(attr_int(g, me, "said_seq") + 1)},
                      {"said_text", Value("Sorry, is it time for lunch already?")},
                      {"said_for", Value(q->seq)}, {"answered", Value(q->seq)}});
      break;
    case ReplyKind::kSilent:
      s = write(ctx, {{"answered", Value(q->seq)}});
      break;
  }
  if (s.ok()) {
    answered_seq_ = q->seq;
    ++answers_;
    ctx.log(std::string("replies to #") + std::to_string(q->seq) + ": " + to_string(r.kind));
  }
}

void Patient::status(nlohmann::json& out) const {
  out["answers"] = answers_;
  out["leaves"] = leaves_;
}

}  // namespace quiver::agents::inline apps::barthel
