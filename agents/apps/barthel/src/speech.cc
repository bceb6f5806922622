// The Speech agent: the Planner's utterances said one at a time while the patient is there (stopped at once
// when the person is lost), and the recognised answers written as `heard`.
#include "quiver/agents/apps/barthel/speech.h"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"

namespace quiver::agents::inline apps::barthel {

using graph::NodeId;
using graph::Symbol;

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

int match_option(std::string_view text, const std::vector<std::string>& options) {
  const std::string t = lower(text);
  int best = -1;
  std::size_t best_len = 0;
  for (std::size_t i = 0; i < options.size(); ++i) {
    const std::string o = lower(options[i]);
    if (!o.empty() && t.find(o) != std::string::npos && o.size() > best_len) {
      best = static_cast<int>(i);
      best_len = o.size();
    }
  }
  return best;
}

class Speech::Speak final : public Action {
 public:
  explicit Speak(Speech& s) : Action("speak"), s_(s) {}

  std::vector<Match> find(AgentContext& ctx) override {
    const graph::Graph& g = ctx.graph();
    for (graph::NodeId id : prompt_ids(g)) {
      if (attr_bool(g, id, "obsolete") || marked(g, node::kSpeaker, edge::kSpoke, id)) continue;
      auto found = prompt_at(g, id);
      if (!found || !eligible(ctx, *found)) continue;
      const Prompt& p = *found;
      Match m;
      m.key = "u" + std::to_string(p.seq) + "@" + p.id.to_string();
      m.nodes["utterance"] = p.id;
      return {m};
    }
    return {};
  }

  bool holds(AgentContext& ctx, const Match& m) override {
    const graph::Graph& g = ctx.graph();
    auto p = prompt_at(g, m.at("utterance"));
    return p && !attr_bool(g, p->id, "obsolete") && eligible(ctx, *p);
  }

  std::optional<LockNeed> lock(AgentContext& ctx, const Match&) override {
    return LockNeed{node_id(ctx.graph(), node::kSpeaker), s_.opt_.lock_priority};
  }

  Status start(AgentContext& ctx, const Match& m) override {
    graph::Graph& g = ctx.graph();
    auto p = prompt_at(g, m.at("utterance"));
    if (!p) return make_error(ErrorCode::kNotFound, "speak: the utterance is gone");
    graph::Transaction tx = g.begin();
    if (Status s = tx.insert_edge(node_id(g, node::kSpeaker), p->id, edge::kSpeaking); !s.ok()) return s;
    if (auto c = tx.commit(); !c.ok()) return c.error();
    auto said = s_.out_->say(p->text, ctx.now());
    if (!said.ok()) {
      unmark(ctx, p->id);
      return said.error();
    }
    ctx.log("says #" + std::to_string(p->seq) + " (" + p->purpose + "): " + p->text);
    return {};
  }

  Progress process(AgentContext& ctx, const Match&) override {
    return s_.out_->playing(ctx.now()) ? Progress::kRunning : Progress::kDone;
  }

  Status finish(AgentContext& ctx, const Match& m) override {
    graph::Graph& g = ctx.graph();
    NodeId sp = node_id(g, node::kSpeaker), u = m.at("utterance");
    graph::Transaction tx = g.begin();
    if (Status s = tx.delete_edge(sp, u, Symbol(edge::kSpeaking)); !s.ok()) return s;
    if (Status s = tx.insert_edge(sp, u, edge::kSpoke); !s.ok()) return s;
    ++s_.spoken_;
    auto c = tx.commit();
    return c.ok() ? Status{} : Status(c.error());
  }

  void cancel(AgentContext& ctx, const Match& m, CancelReason why) override {
    const std::int64_t now = ctx.now();
    s_.out_->stop(now);  // first: the graph cannot undo a spoken sentence
    ++s_.interrupted_;
    const graph::Graph& g = ctx.graph();
    if (!person_present(g)) {
      const std::int64_t lost = attr_int(g, node_id(g, node::kPerson), "lost_ns", 0);
      if (lost > 0 && now >= lost) {
        s_.last_reaction_ns_ = now - lost;
        if (s_.reactions_ns_.size() < kMaxReactionsKept) s_.reactions_ns_.push_back(now - lost);
        if (s_.reaction_cb_) s_.reaction_cb_(Reaction{lost, now});
      }
    }
    std::string line = std::string("stops speaking (") + to_string(why) + (person_present(g) ? "" : ": the person was lost");
    if (!person_present(g) && s_.last_reaction_ns_ >= 0)
      line += ", " + std::to_string(s_.last_reaction_ns_ / 1000) + " us after Person committed the loss";
    ctx.log(line + ")");
    unmark(ctx, m.at("utterance"));
  }

 private:
  bool eligible(AgentContext& ctx, const Prompt& p) const {
    // Calling the patient back is said to the room; everything else to the patient.
    return p.purpose == "call_back" ? !person_present(ctx.graph())
                                    : patient_in_front(ctx.graph(), ctx.now(), s_.opt_.presence_stale_ns);
  }
  static void unmark(AgentContext& ctx, NodeId u) {
    if (Status s = take_back(ctx.graph(), node::kSpeaker, edge::kSpeaking, u); !s.ok())
      ctx.log("could not take back the speaking mark: " + s.error().to_string());
  }
  Speech& s_;
};

Speech::Speech(std::unique_ptr<devices::SpeechOutput> out, std::unique_ptr<SpeechInput> in, SpeechOptions o,
               std::string name)
    : Agent(std::move(name)), out_(std::move(out)), in_(std::move(in)), opt_(o) {
  set_grammar_text(std::string(role_grammar("speech")), "speech.aggl");
}

Speech::~Speech() = default;

void Speech::setup(AgentContext& ctx) {
  // A speaking mark left by an earlier incarnation (killed mid-sentence) goes back to not
  // speaking: that sentence was not said to the end.
  (void)take_back(ctx.graph(), node::kSpeaker, edge::kSpeaking);
  ChangeFilter interest;
  interest.edge_types = {std::string(edge::kSay), std::string(edge::kInFrontOf), std::string(edge::kSpoke)};
  interest.attributes = {"obsolete", "seen_ns", "present"};
  add_action(std::make_unique<Speak>(*this), interest);
  if (in_) ctx.every(opt_.asr_period_ns, [this, &ctx] { poll_asr(ctx); });
}

void Speech::poll_asr(AgentContext& ctx) {
  auto h = in_->last(ctx.graph());
  if (!h || h->seq <= handled_heard_) return;
  graph::Graph& g = ctx.graph();
  auto p = prompt_by_seq(g, h->for_seq);
  NodeId sp = node_id(g, node::kSpeaker);
  if (!p) return;  // not replicated here yet: try again
  handled_heard_ = h->seq;
  if (!p->is_question() || !g.has_edge(sp, p->id, Symbol(edge::kSpoke)) ||
      g.has_edge(sp, p->id, Symbol(edge::kHeard)))
    return;
  const int option = match_option(h->text, p->options);
  graph::Transaction tx = g.begin();
  if (!tx.insert_edge(sp, p->id, edge::kHeard,
                      {{Symbol("option"), graph::Value(static_cast<std::int64_t>(option))},
                       {Symbol("text"), graph::Value(h->text)}})
           .ok())
    return;
  if (auto c = tx.commit(); c.ok()) {
    ++heard_;
    ctx.log("heard \"" + h->text + "\" for #" + std::to_string(p->seq) +
            (option < 0 ? " (not understood)" : " (option " + std::to_string(option) + ")"));
  } else {
    handled_heard_ = h->seq - 1;  // try again
  }
}

void Speech::status(nlohmann::json& out) const {
  out["spoken"] = spoken_;
  out["interrupted"] = interrupted_;
  out["heard"] = heard_;
  if (last_reaction_ns_ >= 0) out["last_reaction_ms"] = last_reaction_ns_ / 1e6;
  auto& us = out["reactions_us"] = nlohmann::json::array();
  for (std::int64_t ns : reactions_ns_) us.push_back(static_cast<double>(ns) / 1e3);
}

}  // namespace quiver::agents::inline apps::barthel
