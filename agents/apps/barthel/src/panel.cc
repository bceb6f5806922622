// The Panel agent: the newest prompt's screen shown (and its picture stored on `panel`) while the patient is
// there, cleared when the person is lost, and the option touched written as `tapped`.
#include "quiver/agents/apps/barthel/panel.h"

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/view/images/image_attrs.h"

namespace quiver::agents::inline apps::barthel {

using graph::NodeId;
using graph::Symbol;

class Panel::Display final : public Action {
 public:
  explicit Display(Panel& p) : Action("display"), p_(p) {}

  std::vector<Match> find(AgentContext& ctx) override {
    auto p = newest(ctx);
    if (!p) return {};
    Match m;
    m.key = "s" + std::to_string(p->seq) + "@" + p->id.to_string();
    m.nodes["utterance"] = p->id;
    return {m};
  }

  bool holds(AgentContext& ctx, const Match& m) override {
    auto p = newest(ctx);
    return p && p->id == m.at("utterance");
  }

  std::optional<LockNeed> lock(AgentContext& ctx, const Match&) override {
    return LockNeed{node_id(ctx.graph(), node::kPanel), p_.opt_.lock_priority};
  }

  Status start(AgentContext& ctx, const Match& m) override {
    graph::Graph& g = ctx.graph();
    auto p = prompt_at(g, m.at("utterance"));
    if (!p) return make_error(ErrorCode::kNotFound, "display: the prompt is gone");
    devices::ScreenContent c;
    c.title = p->title;
    c.text = p->screen_text;
    if (p->buttons) c.options = p->options;
    if (Status s = p_.screen_->show(c, ctx.now()); !s.ok()) return s;
    graph::Transaction tx = g.begin();
    const NodeId panel = node_id(g, node::kPanel);
    if (Status s = tx.insert_edge(panel, p->id, edge::kShowing); !s.ok()) return s;
    p_.store_screen_image(ctx, tx, panel);
    ++p_.shown_;
    auto c2 = tx.commit();
    return c2.ok() ? Status{} : Status(c2.error());
  }

  Progress process(AgentContext&, const Match&) override { return Progress::kRunning; }
  Status finish(AgentContext&, const Match&) override { return {}; }

  void cancel(AgentContext& ctx, const Match& m, CancelReason) override {
    graph::Graph& g = ctx.graph();
    const NodeId panel = node_id(g, node::kPanel);
    {
      graph::Transaction tx = g.begin();
      if (p_.screen_->clear(ctx.now()).ok()) {
        p_.store_screen_image(ctx, tx, panel);  // the blank picture
      } else {
        (void)images::remove_image(tx, panel, kScreenImage);  // what it shows is unknown
      }
      if (!tx.empty()) (void)tx.commit();
    }
    ++p_.cleared_;
    (void)take_back(g, node::kPanel, edge::kShowing, m.at("utterance"));
  }

 private:
  // The newest prompt with something for the screen, while the patient is there and the test runs.
  std::optional<Prompt> newest(AgentContext& ctx) const {
    const graph::Graph& g = ctx.graph();
    if (!patient_in_front(g, ctx.now(), p_.opt_.presence_stale_ns)) return std::nullopt;
    if (attr_string(g, node_id(g, node::kTest), "status") != "running") return std::nullopt;
    const auto ids = prompt_ids(g);
    for (auto it = ids.rbegin(); it != ids.rend(); ++it) {
      if (attr_bool(g, *it, "obsolete")) continue;
      if (auto p = prompt_at(g, *it); p && p->has_screen()) return p;
    }
    return std::nullopt;
  }
  Panel& p_;
};

Panel::Panel(std::unique_ptr<devices::Screen> screen, std::unique_ptr<TouchInput> touch, PanelOptions o,
             std::string name)
    : Agent(std::move(name)), screen_(std::move(screen)), touch_(std::move(touch)), opt_(o) {
  set_grammar_text(std::string(role_grammar("panel")), "panel.aggl");
}

Panel::~Panel() = default;

void Panel::setup(AgentContext& ctx) {
  // A screen mark or picture left by an earlier incarnation: this screen shows nothing yet.
  graph::Graph& g = ctx.graph();
  (void)take_back(g, node::kPanel, edge::kShowing);
  if (const NodeId panel = node_id(g, node::kPanel); !panel.is_null()) {
    graph::Transaction tx = g.begin();
    if (images::remove_image(tx, panel, kScreenImage).ok() && !tx.empty()) (void)tx.commit();
  }
  ChangeFilter interest;
  interest.edge_types = {std::string(edge::kSay), std::string(edge::kInFrontOf)};
  interest.attributes = {"obsolete", "status", "seen_ns", "present"};
  add_action(std::make_unique<Display>(*this), interest);
  if (touch_) ctx.every(opt_.touch_period_ns, [this, &ctx] { poll_touch(ctx); });
}

// Puts the picture the screen now shows on the panel node in `tx`, when the screen renders
// pictures. One that cannot be stored is logged, and the stale one removed: the graph never
// shows what the screen no longer does.
void Panel::store_screen_image(AgentContext& ctx, graph::Transaction& tx, NodeId panel) {
  const std::span<const std::uint8_t> picture = screen_->image();
  if (picture.empty()) return;
  Status s = images::set_encoded_image(tx, panel, graph::Bytes(picture.begin(), picture.end()),
                                       kScreenImage);
  if (s.ok()) {
    ++images_;
    return;
  }
  ctx.log("the screen's picture is not stored: " + s.error().message);
  (void)images::remove_image(tx, panel, kScreenImage);
}

void Panel::poll_touch(AgentContext& ctx) {
  auto t = touch_->last(ctx.graph());
  if (!t || t->seq <= handled_touch_) return;
  graph::Graph& g = ctx.graph();
  auto p = prompt_by_seq(g, t->for_seq);
  if (!p) return;  // not replicated here yet
  NodeId panel = node_id(g, node::kPanel);
  // A touch counts on the screen it was made on, while that shows buttons (a restarted Panel
  // counts it once it shows that screen again).
  if (!p->is_question() || !p->buttons || t->option < 0 || static_cast<std::size_t>(t->option) >= p->options.size() ||
      g.has_edge(panel, p->id, Symbol(edge::kTapped))) {
    handled_touch_ = t->seq;
    return;
  }
  if (!g.has_edge(panel, p->id, Symbol(edge::kShowing))) return;
  handled_touch_ = t->seq;
  graph::Transaction tx = g.begin();
  if (!tx.insert_edge(panel, p->id, edge::kTapped,
                      {{Symbol("option"), graph::Value(static_cast<std::int64_t>(t->option))},
                       {Symbol("text"), graph::Value(p->options[static_cast<std::size_t>(t->option)])}})
           .ok())
    return;
  if (auto c = tx.commit(); c.ok()) {
    ++taps_;
    ctx.log("touched \"" + p->options[static_cast<std::size_t>(t->option)] + "\" for #" + std::to_string(p->seq));
  } else {
    handled_touch_ = t->seq - 1;
  }
}

void Panel::status(nlohmann::json& out) const {
  out["shown"] = shown_;
  out["cleared"] = cleared_;
  out["taps"] = taps_;
  out["images"] = images_;
}

}  // namespace quiver::agents::inline apps::barthel
